#pragma once
// Files a user names (configs, scenes, meshes, materials): read whole, with the reason a path is
// not a readable file, and file names checked to be UTF-8, since results record them in JSON.

#include <filesystem>
#include <string>

namespace gibench {

// The bytes of `file`. Throws InputError `<prefix><reason>`, the reason being the system's
// ("No such file or directory") or "is a directory, not a file".
std::string readInputFile(const std::filesystem::path& file, const std::string& prefix);

// Throws InputError "<file>: expected a file name in UTF-8 (...), got byte 0xNN at offset K" when
// the path is not valid UTF-8; the file name is quoted with such bytes as \xNN.
void checkUtf8Path(const std::filesystem::path& file);
// The same for text from the command line: InputError "<what> \"<text>\": expected UTF-8 (...)".
void checkUtf8Text(const std::string& text, const std::string& what);

}  // namespace gibench
