// ExrHeaderCheck: a valid OpenEXR file passes; a header whose attribute size the file
// cannot hold, a data window whose pixels the file cannot decode to, a header that runs
// past the end and a file that is not OpenEXR are Errors, found by walking the header,
// before OpenEXR allocates what the header declares.
#include "DemTestSupport.h"

#include "terrain/pyramid/ExrHeaderCheck.h"
#include "terrain/dem/HeightImageWriter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

namespace terrain::io {
namespace {

using test::TempDir;

class ExrHeaderCheckTest : public ::testing::Test {
protected:
    void SetUp() override {
        const std::vector<float> heights(16 * 8, 3.5F);
        ASSERT_TRUE(writeHeightImage(m_dir.file("valid.exr"), 16, 8, heights));
        m_valid = test::readBytes(m_dir.file("valid.exr"));
        ASSERT_GT(m_valid.size(), 64u);
    }
    std::string write(const std::string& name, const std::vector<char>& bytes) {
        const std::string path = m_dir.file(name);
        test::writeBytes(path, bytes);
        return path;
    }
    // The offset of the first attribute's 4-byte size: after the 8-byte start, its name
    // and its type, each null-terminated.
    std::size_t firstSizeOffset() const {
        std::size_t at = 8;
        for (int strings = 0; strings < 2; ++at)
            if (m_valid[at] == '\0') ++strings;
        return at;
    }

    TempDir m_dir;
    std::vector<char> m_valid;
};

TEST_F(ExrHeaderCheckTest, ValidFilePasses) {
    const Status ok = checkExrHeaderSizes(m_dir.file("valid.exr"));
    EXPECT_TRUE(ok) << ok.error().message;
}

TEST_F(ExrHeaderCheckTest, AttributeLongerThanTheFileIsAnError) {
    std::vector<char> damaged = m_valid;
    const std::int32_t huge = 0x7FFFFFF0;
    std::memcpy(damaged.data() + firstSizeOffset(), &huge, sizeof huge);
    const Status s = checkExrHeaderSizes(write("huge.exr", damaged));
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("corrupt OpenEXR header 0"), std::string::npos)
        << s.error().message;
    EXPECT_NE(s.error().message.find("2147483632 bytes"), std::string::npos) << s.error().message;
}

TEST_F(ExrHeaderCheckTest, NegativeSizeIsAnError) {
    std::vector<char> damaged = m_valid;
    const std::int32_t negative = -4;
    std::memcpy(damaged.data() + firstSizeOffset(), &negative, sizeof negative);
    EXPECT_FALSE(checkExrHeaderSizes(write("negative.exr", damaged)));
}

TEST_F(ExrHeaderCheckTest, TruncatedHeaderIsAnError) {
    for (std::size_t length : {std::size_t{0}, std::size_t{4}, std::size_t{8}, firstSizeOffset(),
                               firstSizeOffset() + 6}) {
        const std::vector<char> prefix(m_valid.begin(),
                                       m_valid.begin() + static_cast<std::ptrdiff_t>(length));
        EXPECT_FALSE(checkExrHeaderSizes(write("prefix.exr", prefix))) << length << " bytes";
    }
}

// The file fuzz-dem-exr found: a data window of 8.4M columns in a file of a few hundred
// bytes, which OpenEXR would allocate and fill (300 MB) before finding no chunks.
TEST_F(ExrHeaderCheckTest, DataWindowLargerThanTheFileCanDecodeToIsAnError) {
    const std::string key("dataWindow\0box2i\0", 17);
    const auto at = std::search(m_valid.begin(), m_valid.end(), key.begin(), key.end());
    ASSERT_NE(at, m_valid.end());
    // After the key: the 4-byte size, then xMin, yMin, xMax, yMax.
    const std::size_t xMax = static_cast<std::size_t>(at - m_valid.begin()) + key.size() + 4 + 8;
    std::vector<char> damaged = m_valid;
    const std::int32_t wide = 8388607;
    std::memcpy(damaged.data() + xMax, &wide, sizeof wide);
    const Status s = checkExrHeaderSizes(write("wide.exr", damaged));
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("its 8388608 × 8 data window (1 channels) decodes to"),
              std::string::npos)
        << s.error().message;
}

// The bound is each codec's largest possible expansion, so the most compressible real file
// still passes: a constant image, which deflate packs as tightly as it can.
TEST_F(ExrHeaderCheckTest, ConstantImagePasses) {
    constexpr int kSide = 2048;
    const std::vector<float> heights(std::size_t{kSide} * kSide, 0.0F);
    ASSERT_TRUE(writeHeightImage(m_dir.file("flat.exr"), kSide, kSide, heights));
    const Status ok = checkExrHeaderSizes(m_dir.file("flat.exr"));
    EXPECT_TRUE(ok) << ok.error().message;
    const auto bytes = test::readBytes(m_dir.file("flat.exr")).size();
    EXPECT_LT(4.0 * kSide * kSide / static_cast<double>(bytes), 1032.0)
        << "deflate's limit is 1032:1: " << bytes << " bytes";
}

TEST_F(ExrHeaderCheckTest, OtherFilesAreErrors) {
    EXPECT_FALSE(checkExrHeaderSizes(write("text.exr", {'h', 'e', 'l', 'l', 'o', '!', '!', '!'})));
    EXPECT_FALSE(checkExrHeaderSizes(m_dir.file("missing.exr")));
}

}  // namespace
}  // namespace terrain::io
