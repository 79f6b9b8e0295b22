#include "experiments/output_dir.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace gibench {
namespace {

constexpr const char* kStaging = ".staging-";
constexpr const char* kOld = ".old-";
constexpr const char* kTemporary = ".tmp-";

// "PID-N": this process and a number no other name of this process has.
std::string ownerTag() {
    static std::atomic<unsigned> counter{0};
    return std::to_string(getpid()) + "-" + std::to_string(counter++);
}

std::filesystem::path ownedName(const std::filesystem::path& finalPath, const char* prefix, const std::string& tag) {
    return finalPath.parent_path() / (prefix + finalPath.filename().string() + "-" + tag);
}

// A leftover's name taken apart: PREFIX NAME "-" PID "-" N.
struct Leftover {
    std::filesystem::path path;
    std::string prefix;
    std::string name;
    std::string tag;  // "PID-N"
    pid_t pid = 0;
};

bool allDigits(const std::string& s) { return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos; }

std::optional<Leftover> parseLeftover(const std::filesystem::path& path) {
    const std::string file = path.filename().string();
    for (const char* prefix : {kStaging, kOld, kTemporary}) {
        const std::string p = prefix;
        if (file.rfind(p, 0) != 0) continue;
        const auto counterDash = file.rfind('-');
        if (counterDash == std::string::npos || counterDash <= p.size()) return std::nullopt;
        const auto pidDash = file.rfind('-', counterDash - 1);
        if (pidDash == std::string::npos || pidDash < p.size()) return std::nullopt;
        const std::string pid = file.substr(pidDash + 1, counterDash - pidDash - 1);
        if (!allDigits(pid) || !allDigits(file.substr(counterDash + 1)) || pid.size() > 9) return std::nullopt;
        return Leftover{path, p, file.substr(p.size(), pidDash - p.size()), file.substr(pidDash + 1), pid_t(std::stol(pid))};
    }
    return std::nullopt;
}

// EPERM means a process of another user holds the PID: alive.
bool processGone(pid_t pid) { return pid > 0 && kill(pid, 0) != 0 && errno == ESRCH; }

}  // namespace

void cleanAbandoned(const std::filesystem::path& folder) {
    std::error_code error;
    std::vector<Leftover> abandoned;
    for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
        const std::optional<Leftover> leftover = parseLeftover(entry.path());
        if (leftover && processGone(leftover->pid)) abandoned.push_back(*leftover);
    }
    // Old folders first: rolling a commit back decides what its staging folder is (then removed).
    for (const Leftover& old : abandoned)
        if (old.prefix == kOld) {
            const std::filesystem::path result = folder / old.name;
            if (std::filesystem::exists(result, error))
                std::filesystem::remove_all(old.path, error);
            else
                std::filesystem::rename(old.path, result, error);
        }
    for (const Leftover& other : abandoned)
        if (other.prefix != kOld) std::filesystem::remove_all(other.path, error);
}

StagingDir::StagingDir(std::filesystem::path finalPath) : m_final(std::move(finalPath)) {
    const std::string tag = ownerTag();
    m_staging = ownedName(m_final, kStaging, tag);
    m_old = ownedName(m_final, kOld, tag);
    const std::filesystem::path folder = m_final.parent_path();
    cleanAbandoned(folder);
    for (std::filesystem::path p = folder; !p.empty() && !std::filesystem::exists(p); p = p.parent_path()) {
        m_created = p;
        if (p == p.parent_path()) break;
    }
    std::filesystem::create_directories(m_staging);
}

StagingDir::~StagingDir() {
    if (m_committed) return;
    std::error_code ignored;
    std::filesystem::remove_all(m_staging, ignored);
    if (m_created.empty()) return;
    // Innermost first; remove() leaves a folder that is not empty (another run wrote into it).
    for (std::filesystem::path p = m_final.parent_path();; p = p.parent_path()) {
        if (!std::filesystem::remove(p, ignored) || p == m_created) break;
    }
}

void StagingDir::commit() {
    const bool replacing = std::filesystem::exists(m_final);
    if (replacing) std::filesystem::rename(m_final, m_old);
    try {
        std::filesystem::rename(m_staging, m_final);
    } catch (...) {
        std::error_code ignored;
        if (replacing) std::filesystem::rename(m_old, m_final, ignored);
        throw;
    }
    m_committed = true;
    // A failure here leaves only an abandoned ".old-*" that the next run in the folder removes.
    std::error_code ignored;
    if (replacing) std::filesystem::remove_all(m_old, ignored);
}

TemporaryFile::TemporaryFile(std::filesystem::path finalPath)
    : m_final(std::move(finalPath)), m_temporary(ownedName(m_final, kTemporary, ownerTag())) {}

TemporaryFile::~TemporaryFile() {
    if (m_committed) return;
    std::error_code ignored;
    std::filesystem::remove(m_temporary, ignored);
}

void TemporaryFile::commit() {
    std::filesystem::rename(m_temporary, m_final);
    m_committed = true;
}

void writeFileAtomically(const std::filesystem::path& file, const std::string& text) {
    TemporaryFile temporary(file);
    {
        std::ofstream out(temporary.path(), std::ios::binary);
        out << text;
        out.close();
        if (!out) throw std::runtime_error(temporary.path().string() + ": cannot write");
    }
    temporary.commit();
}

}  // namespace gibench
