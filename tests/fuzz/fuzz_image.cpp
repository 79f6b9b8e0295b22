// Fuzz target: the input's first byte picks the file type (even: EXR, odd: PNG), the rest is the
// file, read through every image reader gibench has: readLayeredImage (references, `compare`) and
// loadTexture (albedo and environment maps).

#include "core/image/image.h"
#include "core/scene/texture_io.h"
#include "fuzz_outcome.h"
#include "private_folder.h"

#include <cstdint>
#include <string_view>

namespace {

const gibench::PrivateFolder& folder() {
    static const gibench::PrivateFolder instance("fuzz_image");
    return instance;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace gibench;
    if (size == 0) return 0;
    folder().empty();
    const auto file = folder().write(data[0] % 2 == 0 ? "image.exr" : "image.png",
                                     std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1));
    acceptsOrRejectsCleanly([&] { readLayeredImage(file); });
    acceptsOrRejectsCleanly([&] { loadTexture(file); });
    return 0;
}
