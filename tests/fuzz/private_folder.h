#pragma once
// The folder a fuzz target writes its input files into: one per target and process, emptied
// before every input so that an input's outcome never depends on the inputs before it (a crash
// file reproduces on its own), and removed when the fuzzer exits normally. It lies under $TMPDIR
// (default /tmp): run_fuzzers.sh points that at a folder of its own, which it removes even after
// a crash.

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace gibench {

class PrivateFolder {
public:
    explicit PrivateFolder(const std::string& target) {
        const char* tmp = std::getenv("TMPDIR");
        m_path = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") / ("gibench_" + target + "_" + std::to_string(getpid()));
        empty();
    }
    ~PrivateFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(m_path, ignored);
    }
    PrivateFolder(const PrivateFolder&) = delete;
    PrivateFolder& operator=(const PrivateFolder&) = delete;

    // Removes whatever the previous input left.
    void empty() const {
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }

    // Writes `bytes` to `name` in the folder and returns its path.
    std::filesystem::path write(const std::string& name, std::string_view bytes) const {
        const std::filesystem::path file = m_path / name;
        std::ofstream(file, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return file;
    }

    const std::filesystem::path& path() const { return m_path; }

private:
    std::filesystem::path m_path;
};

}  // namespace gibench
