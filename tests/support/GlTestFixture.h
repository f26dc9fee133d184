// GlTestFixture: one headless OpenGL 4.5 context per test suite (EGL, llvmpipe where there
// is no GPU); a test fails when the GL debug output recorded any error while it ran.
//   class MyTest : public terrain::test::GlTest {};
//   class MyParamTest : public terrain::test::GlTestWithParam<Levels> {};
#pragma once

#include "terrain/gl/HeadlessGlContext.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace terrain::test {

template <typename Base>
class BasicGlTest : public Base {
public:
    static void SetUpTestSuite() {
        auto created = gl::HeadlessGlContext::create();
        if (created) {
            state().context = std::move(created).value();
        } else {
            state().error = created.error().message;
        }
    }

    static void TearDownTestSuite() {
        state().context.reset();
        state().error.clear();
    }

protected:
    void SetUp() override {
        ASSERT_NE(state().context, nullptr) << "no GL context: " << state().error;
        const Status current = state().context->makeCurrent();
        ASSERT_TRUE(current) << current.error().message;
        state().context->debugLog().clear();
    }

    void TearDown() override {
        if (!state().context) {
            return;
        }
        gl::GlDebugLog& log = state().context->debugLog();
        EXPECT_EQ(log.errorCount(), 0u) << "GL debug output reported errors:\n"
                                        << log.formatErrors();
        log.clear();
    }

    static gl::HeadlessGlContext& context() { return *state().context; }
    static gl::GlDebugLog& debugLog() { return state().context->debugLog(); }

private:
    struct State {
        std::unique_ptr<gl::HeadlessGlContext> context;
        std::string error;
    };
    static State& state() {
        static State instance;
        return instance;
    }
};

using GlTest = BasicGlTest<::testing::Test>;

template <typename Param>
using GlTestWithParam = BasicGlTest<::testing::TestWithParam<Param>>;

}  // namespace terrain::test
