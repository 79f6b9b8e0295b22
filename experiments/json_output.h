#pragma once
// What gibench writes as JSON (manifests, metrics, frames.jsonl, reference records, `compare`'s
// output) is JSON every reader takes: strings are UTF-8 and numbers finite. nlohmann::json checks
// neither in time: it throws on a non-UTF-8 string only when dumping, i.e. after the whole render,
// and silently writes NaN and infinities as null.

#include "core/config/params.h"

#include <string>

namespace gibench {

// Throws InputError "SOURCE: DOCUMENT's /POINTER: " + checkUtf8Path()'s message for the first
// string or key of `value` that is not valid UTF-8. `source` is the file whose reading put it
// there (the config), `document` the JSON file that would hold it ("the manifest"). Call it
// before the work whose results the JSON records.
void requireUtf8(const Json& value, const std::string& source, const std::string& document);

// value.dump(indent); std::logic_error naming the JSON pointer of the first number that is NaN or
// infinite, since every input is checked before and such a number is a defect.
std::string dumpFinite(const Json& value, int indent = -1);

}  // namespace gibench
