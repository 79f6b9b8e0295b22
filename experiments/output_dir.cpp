#include "experiments/output_dir.h"

#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace gibench {

static std::string uniqueSuffix() { return std::to_string(getpid()) + "-" + std::to_string(std::rand()); }

StagingDir::StagingDir(std::filesystem::path finalPath) : m_final(std::move(finalPath)) {
    m_staging = m_final.parent_path() / (".staging-" + m_final.filename().string() + "-" + uniqueSuffix());
    std::filesystem::create_directories(m_staging);
}

StagingDir::~StagingDir() {
    if (!m_committed) {
        std::error_code ignored;
        std::filesystem::remove_all(m_staging, ignored);
    }
}

void StagingDir::commit() {
    std::filesystem::path old;
    if (std::filesystem::exists(m_final)) {
        old = m_final.parent_path() / (".old-" + m_final.filename().string() + "-" + uniqueSuffix());
        std::filesystem::rename(m_final, old);
    }
    std::filesystem::rename(m_staging, m_final);
    m_committed = true;
    if (!old.empty()) std::filesystem::remove_all(old);
}

void writeFileAtomically(const std::filesystem::path& file, const std::string& text) {
    const std::filesystem::path temporary = file.parent_path() / (".tmp-" + file.filename().string() + "-" + uniqueSuffix());
    {
        std::ofstream out(temporary, std::ios::binary);
        out << text;
        if (!out) throw std::runtime_error(temporary.string() + ": cannot write");
    }
    std::filesystem::rename(temporary, file);
}

}  // namespace gibench
