#pragma once
// Command-line overrides of a run config (`gibench run CONFIG --set method.spp=64 --set
// camera.resolution=[128,128]`): each sets one key, named by its dotted path from the config's
// top, to a JSON value before the config is read, so the value is typed and checked exactly as
// the file's would be, and the manifest's resolved config holds it (with the override texts under
// "overrides").
//
// KEY is one or more names separated by dots (each 1 to 64 letters, digits, '_' or '-'); objects
// missing on the way are created, and a name through a value that is not an object is an error.
// VALUE is parsed as JSON (64, 2.5, true, [128,128], {"a":1}, "text"); text that is not JSON is
// taken as a string, so `--set method.sampler=sobol` needs no quotes (a string that reads as JSON,
// such as a run named 123, does: `--set 'run="123"'`).

#include "core/config/params.h"

#include <string>
#include <vector>

namespace gibench {

struct ConfigOverride {
    std::string text;                // as given, KEY=VALUE
    std::vector<std::string> path;   // KEY split at its dots
    Json value;
    std::string source;              // where it came from, for messages: "on the command line: --set TEXT"
    // "/a/b", the JSON pointer of the key: how error messages about it name it.
    std::string pointer() const;
};

// InputError naming `--set` and the text when it is not KEY=VALUE as above.
ConfigOverride parseConfigOverride(const std::string& text);

// Sets every override in `config` in order (a later one wins); InputError naming the override when
// a name on its path holds a value that is not an object.
void applyConfigOverrides(Json& config, const std::vector<ConfigOverride>& overrides);

// `message` (an InputError's) followed by a line naming each override whose key it is about
// ("POINTER was set SOURCE"), so an error in an overridden value points at where it came from,
// not only at the file.
std::string withOverrideOrigins(const std::string& message, const std::vector<ConfigOverride>& overrides);

}  // namespace gibench
