#pragma once
// Results appear whole or not at all, even when gibench is killed. A run writes into a hidden
// staging folder beside its final place and renames it there only when everything is written; a
// file (a reference image, a JSON record) is written under a temporary name and renamed. Failures
// remove what they wrote, and folders they created.
//
// What a killed process leaves is cleaned by the next one writing into the same folder. Names say
// whose a leftover is: ".staging-NAME-PID-N", ".old-NAME-PID-N" and ".tmp-NAME-PID-N", PID the
// writing process and N a counter within it (one commit uses one PID-N for its staging and old
// folder). A leftover whose process is gone (kill(PID, 0) fails with ESRCH) is abandoned:
//   - ".staging-*": an unfinished run: removed.
//   - ".old-*": the earlier result a commit moved aside before renaming its staging folder in.
//     When NAME exists, the commit finished: the old folder is removed. When it does not, the
//     process died between the two renames: the commit did not happen, so it is rolled back (the
//     old folder becomes NAME again, the staging folder is removed) — a run that did not finish
//     leaves no trace, whether it was killed while rendering or while renaming.
//   - ".tmp-*": a half-written file: removed.
// Leftovers of live processes (another run writing now) are left alone. PIDs are those of this
// machine and PID namespace; a reused PID only delays the clean-up.

#include <filesystem>
#include <string>

namespace gibench {

class StagingDir {
public:
    // Cleans abandoned leftovers in the final path's folder, then creates the staging folder (and
    // the folders above it that are missing).
    explicit StagingDir(std::filesystem::path finalPath);
    ~StagingDir();  // unless commit() ran: removes the staging folder and the folders it created
    StagingDir(const StagingDir&) = delete;
    StagingDir& operator=(const StagingDir&) = delete;

    const std::filesystem::path& path() const { return m_staging; }
    // Moves the staging folder to the final path, replacing an earlier result there (which is
    // restored if the move fails).
    void commit();

private:
    std::filesystem::path m_final;
    std::filesystem::path m_staging;
    std::filesystem::path m_old;      // where an earlier result is moved aside during commit()
    std::filesystem::path m_created;  // the outermost folder the constructor created, or empty
    bool m_committed = false;
};

// A file written under a temporary name in the folder of `finalPath`, renamed to it by commit();
// the destructor removes it unless committed.
class TemporaryFile {
public:
    explicit TemporaryFile(std::filesystem::path finalPath);
    ~TemporaryFile();
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;

    const std::filesystem::path& path() const { return m_temporary; }
    void commit();

private:
    std::filesystem::path m_final;
    std::filesystem::path m_temporary;
    bool m_committed = false;
};

// Writes `text` to `file` through a TemporaryFile.
void writeFileAtomically(const std::filesystem::path& file, const std::string& text);

// Removes or restores, as described above, what processes that are gone left in `folder`
// (nothing when it does not exist). Best effort: an entry that cannot be cleaned stays.
void cleanAbandoned(const std::filesystem::path& folder);

}  // namespace gibench
