#include "core/util/exr_header_check.h"

#include "core/image/image.h"
#include "core/scene/texture_io.h"
#include "core/util/error.h"
#include "support/hostile_images.h"
#include "support/temp_folder.h"

#include <gtest/gtest.h>

#include <string>

namespace gibench {
namespace {

// An OpenEXR start whose "channels" attribute claims 2^31 - 1 bytes in a 40-byte file: OpenEXR
// zero-fills 2 GiB before it sees the file end (fuzz_image found this as an out-of-memory).
std::string hostileExr() {
    std::string bytes("\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
    bytes += std::string("channels\0chlist\0", 16);
    bytes += std::string("\xff\xff\xff\x7f", 4);
    bytes += std::string(12, '\0');
    return bytes;
}

std::string errorOf(const auto& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    } catch (const std::exception& e) {
        return std::string("not an InputError: ") + e.what();
    }
    return "";
}

TEST(ExrHeaderCheck, AnAttributeLargerThanTheRestOfTheFileIsRefusedByEveryReader) {
    TempFolder dir;
    const auto file = dir.write("hostile.exr", hostileExr());
    const std::string expected =
        file.string() + ": cannot read image: not a valid OpenEXR file: attribute \"channels\" claims 2147483647 bytes, but 12 remain in the file";
    EXPECT_EQ(errorOf([&] { checkExrHeader(file); }), expected);
    EXPECT_EQ(errorOf([&] { readLayeredImage(file); }), expected);
    EXPECT_EQ(errorOf([&] { loadTexture(file); }), expected);
}

TEST(ExrHeaderCheck, AHeaderCutShortIsRefusedAndOtherFilesAreLeftToTheLibrary) {
    TempFolder dir;
    const std::string exr = hostileExr();
    EXPECT_NE(errorOf([&] { checkExrHeader(dir.write("cut.exr", exr.substr(0, 14))); }).find("the header ends inside an attribute name"),
              std::string::npos);
    EXPECT_EQ(errorOf([&] { checkExrHeader(dir.write("not_exr.png", "not an image")); }), "");
    // A real file passes, and its layers read back.
    LayeredImage image(3, 2);
    image.add("total", {"R", "G", "B"});
    const auto good = dir.path() / "good.exr";
    writeExr(good, image);
    EXPECT_EQ(errorOf([&] { checkExrHeader(good); }), "");
    EXPECT_EQ(readLayeredImage(good).width, 3);
}

// One row of 2^25 RGB pixels is 10^8 values, within kMaxImageValues, but "zip" compresses 16
// rows per block and OpenEXR sizes its buffers to a block when it opens the file: 1.6 x 10^9
// values, refused before the library sees the file.
TEST(ExrHeaderCheck, ABlockOfScanlinesLargerThanTheLimitIsRefusedBeforeTheLibraryOpensTheFile) {
    TempFolder dir;
    const auto file = dir.write("wide.exr", test::exrClaiming(dir.path() / "scratch.exr", 1 << 25, 1));
    const std::string expected = file.string() +
                                 ": cannot read image: the header claims 33554432x1 pixels of 3 channels, 1610612736 values to decode, "
                                 "more than the 1073741824 gibench reads";
    EXPECT_EQ(errorOf([&] { checkExrHeader(file); }), expected);
    EXPECT_EQ(errorOf([&] { readLayeredImage(file); }), expected);
    EXPECT_EQ(errorOf([&] { loadTexture(file); }), expected);
    // The same file claiming what its block can hold passes the check.
    EXPECT_EQ(errorOf([&] { checkExrHeader(dir.write("narrow.exr", test::exrClaiming(dir.path() / "scratch.exr", 1 << 20, 1))); }), "");
}

// Found by fuzz_image: a "chlist" one byte longer than its declared size. The walk then saw the
// header end after "channels" and passed the file, while OpenEXR reads the list to its NUL, goes
// on to the dataWindow of 16777218 x 1 pixels and allocates for it in open(). A header without a
// dataWindow (a required attribute) is refused.
TEST(ExrHeaderCheck, AHeaderWalkedToNoDataWindowIsRefused) {
    TempFolder dir;
    std::string bytes = test::exrClaiming(dir.path() / "scratch.exr", 16777218, 1);
    const std::string key("channels\0chlist\0", 16);
    const std::size_t at = bytes.find(key);
    ASSERT_NE(at, std::string::npos);
    --bytes[at + key.size()];  // the declared size, little-endian: one byte short
    const auto file = dir.write("short_chlist.exr", bytes);
    const std::string expected = file.string() + ": cannot read image: not a valid OpenEXR file: the header has no dataWindow attribute of 16 bytes";
    EXPECT_EQ(errorOf([&] { checkExrHeader(file); }), expected);
    EXPECT_EQ(errorOf([&] { readLayeredImage(file); }), expected);
    EXPECT_EQ(errorOf([&] { loadTexture(file); }), expected);
}

}  // namespace
}  // namespace gibench
