// The README's layout section and docs/architecture.md name the folders that exist, and only those.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace gibench {
namespace {

namespace fs = std::filesystem;

const fs::path kRoot = GIBENCH_SOURCE_DIR;
const std::string kStores = "methods/probe_cache/stores/";

std::string readFile(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Folders below core/, methods/ and experiments/ that hold sources: the layers.
std::set<std::string> sourceFolders() {
    std::set<std::string> folders;
    for (const char* top : {"core", "methods", "experiments"})
        for (const auto& entry : fs::recursive_directory_iterator(kRoot / top)) {
            const std::string ext = entry.path().extension().string();
            if (entry.is_regular_file() && (ext == ".h" || ext == ".cpp"))
                folders.insert(fs::relative(entry.path().parent_path(), kRoot).generic_string());
        }
    return folders;
}

std::string layoutSection() {
    const std::string readme = readFile(kRoot / "README.md");
    const std::size_t start = readme.find("## Layout");
    EXPECT_NE(start, std::string::npos) << "README.md has no Layout section";
    const std::size_t end = readme.find("\n## ", start + 1);
    return readme.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

TEST(Layout, ReadmeNamesEverySourceFolder) {
    const std::string layout = layoutSection();
    for (const std::string& folder : sourceFolders()) {
        const bool store = folder.rfind(kStores, 0) == 0;
        const std::string name = store ? folder.substr(kStores.size()) : folder;
        EXPECT_NE(layout.find("`" + name + "/`"), std::string::npos) << "README.md's layout does not name " << folder << "/";
    }
}

TEST(Layout, EveryFolderTheReadmeNamesExists) {
    const std::string layout = layoutSection();
    const std::regex path("`([a-z_]+(/[a-z_]+)*)/`");
    int named = 0;
    for (auto it = std::sregex_iterator(layout.begin(), layout.end(), path); it != std::sregex_iterator(); ++it) {
        const std::string folder = (*it)[1];
        ++named;
        EXPECT_TRUE(fs::is_directory(kRoot / folder) || fs::is_directory(kRoot / kStores / folder))
            << "README.md's layout names " << folder << "/, which does not exist";
    }
    EXPECT_GT(named, 10);
}

TEST(Layout, ArchitectureTableHasARowPerLayer) {
    const std::string architecture = readFile(kRoot / "docs/architecture.md");
    for (const std::string& folder : sourceFolders()) {
        const bool store = folder.rfind(kStores, 0) == 0;
        const std::string row = "| `" + (store ? kStores + "<store>" : folder) + "` |";
        EXPECT_NE(architecture.find(row), std::string::npos) << "docs/architecture.md has no row " << row;
    }
}

}  // namespace
}  // namespace gibench
