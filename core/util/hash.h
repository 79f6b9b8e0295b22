#pragma once
// Content hashes: SHA-256 as lowercase hex, the same digest `sha256sum` prints.

#include <filesystem>
#include <string>
#include <string_view>

namespace gibench {

std::string sha256Hex(std::string_view bytes);
// Throws InputError naming the file when it cannot be read.
std::string sha256File(const std::filesystem::path& file);

}  // namespace gibench
