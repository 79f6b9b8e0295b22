#include "experiments/parameter_docs.h"

#include "methods/registry.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace gibench {
namespace {

TEST(ParameterDocs, CommittedReferenceIsWhatTheCodeGenerates) {
    const std::string file = std::string(GIBENCH_SOURCE_DIR) + "/docs/parameters.md";
    std::ifstream in(file, std::ios::binary);
    ASSERT_TRUE(in) << file;
    std::stringstream committed;
    committed << in.rdbuf();
    EXPECT_EQ(committed.str(), parameterReferenceMarkdown())
        << file << " is stale: regenerate it with `build/gibench keys > docs/parameters.md`";
}

TEST(ParameterDocs, EveryKeyOfEveryMethodIsDocumented) {
    const std::string markdown = parameterReferenceMarkdown();
    for (const MethodInfo& method : methodRegistry()) {
        EXPECT_NE(markdown.find("`" + method.name + "`"), std::string::npos) << method.name;
        for (const ParamSpec& spec : method.parameters)
            EXPECT_NE(markdown.find("| `" + spec.name + "` |"), std::string::npos) << method.name << "." << spec.name;
    }
}

}  // namespace
}  // namespace gibench
