// runtime::LodMethod: every method has a unique name the flags accept, "all" lists them
// (the default first), and a bad or repeated name is an error that lists the names there are.
#include "terrain/runtime/LodMethod.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace terrain::test {
namespace {

TEST(LodMethodTest, NamesRoundTripAndAllListsEveryMethodDefaultFirst) {
    std::set<std::string> names;
    for (const runtime::LodMethodInfo& info : runtime::lodMethods()) {
        EXPECT_TRUE(names.insert(std::string(info.name)).second) << info.name;
        auto parsed = runtime::parseLodMethod(info.name);
        ASSERT_TRUE(parsed) << parsed.error().message;
        EXPECT_EQ(parsed.value(), info.method);
        EXPECT_EQ(runtime::lodMethodName(info.method), info.name);
        EXPECT_FALSE(info.summary.empty());
    }
    auto all = runtime::parseLodMethods("all");
    ASSERT_TRUE(all) << all.error().message;
    EXPECT_EQ(all.value().size(), runtime::lodMethods().size());
    EXPECT_EQ(all.value().front(), runtime::LodMethod::Yusov2011);
    auto two = runtime::parseLodMethods("rtin, chunked-lod");
    ASSERT_TRUE(two) << two.error().message;
    EXPECT_EQ(two.value(), (std::vector{runtime::LodMethod::Rtin, runtime::LodMethod::ChunkedLod}));
}

TEST(LodMethodTest, UnknownAndRepeatedNamesAreErrorsThatListTheMethods) {
    auto unknown = runtime::parseLodMethods("yusov2011,roam");
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("'roam'"), std::string::npos) << unknown.error().message;
    EXPECT_NE(unknown.error().message.find("chunked-lod"), std::string::npos);
    auto twice = runtime::parseLodMethods("rtin,rtin");
    ASSERT_FALSE(twice);
    EXPECT_NE(twice.error().message.find("twice"), std::string::npos) << twice.error().message;
    EXPECT_FALSE(runtime::parseLodMethods(""));
}

}  // namespace
}  // namespace terrain::test
