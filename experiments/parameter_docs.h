#pragma once
// The parameter reference of every method as Markdown (`gibench methods --markdown`), generated
// from the same tables that read configs, so the reference (docs/parameters.md) cannot drift from
// the code: a test compares the committed file with this output.

#include <string>

namespace gibench {

std::string parameterReferenceMarkdown();

}  // namespace gibench
