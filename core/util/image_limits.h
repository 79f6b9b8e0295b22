#pragma once
// The largest image gibench reads, as a file or as a texture.

namespace gibench {

// The most float values (width × height × channels) an image may hold: 2^30, 4 GiB. Headers are
// checked against it before any pixel is allocated, so a corrupt or hostile header (100000 ×
// 100000 pixels in a 100-byte PNG) is an error naming the file, not an allocation failure.
// Fuzz builds lower it (CMakeLists.txt), so that the fuzzer spends its time in the parsers rather
// than filling gigabytes for every header it enlarges; tests/image cover the full limit.
#ifndef GIBENCH_MAX_IMAGE_VALUES
#define GIBENCH_MAX_IMAGE_VALUES (1 << 30)
#endif
inline constexpr double kMaxImageValues = double(GIBENCH_MAX_IMAGE_VALUES);

}  // namespace gibench
