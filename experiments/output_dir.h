#pragma once
// Results appear whole or not at all: a run writes into a hidden staging folder beside its final
// place and renames it there only when everything is written. An interrupted run leaves a
// ".staging-*" folder, never a results folder that looks complete.

#include <filesystem>
#include <string>

namespace gibench {

class StagingDir {
public:
    explicit StagingDir(std::filesystem::path finalPath);
    ~StagingDir();  // removes the staging folder unless commit() ran
    StagingDir(const StagingDir&) = delete;
    StagingDir& operator=(const StagingDir&) = delete;

    const std::filesystem::path& path() const { return m_staging; }
    // Moves the staging folder to the final path, replacing an earlier result there.
    void commit();

private:
    std::filesystem::path m_final;
    std::filesystem::path m_staging;
    bool m_committed = false;
};

// Writes `text` to `file` through a temporary file and a rename.
void writeFileAtomically(const std::filesystem::path& file, const std::string& text);

}  // namespace gibench
