#pragma once
// A check of an OpenEXR file's header before the image library reads it: OpenEXR allocates and
// zero-fills every attribute at the size the file claims before it finds the file too short, so
// a few hostile bytes ask for gigabytes, and it sizes its decompression buffers from the claimed
// width and rows per block when it opens the file (both found by tests/fuzz/fuzz_image).

#include <filesystem>

namespace gibench {

// Throws InputError naming `file` when it starts as an OpenEXR file (magic 76 2f 31 01) whose
// header is cut short, declares an attribute larger than the rest of the file, or declares more
// pixels to decode at once than kMaxImageValues; returns for every other file, which the image
// library judges itself.
void checkExrHeader(const std::filesystem::path& file);

}  // namespace gibench
