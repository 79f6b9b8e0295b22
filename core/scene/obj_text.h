#pragma once
// Checks of OBJ and MTL text that tinyobjloader does not make. It reads "nan", "1e39" or "abc"
// in place of a number as 0 or infinity, a Kd of one number as (r, 0, 0), binary garbage as an
// empty model, and resolves a face index out of range or an mtllib path without naming the line.
// Each check throws InputError "<where><file>:<line>: <keyword>: <what>" (lines from 1).

#include <filesystem>
#include <string>

namespace gibench {

// The OBJ `text` of `file`: it is text (no control bytes but tab, line and page breaks); the
// numbers of v (x y z), vn (x y z) and vt (u [v]) lines are decimal numbers that fit a float; face
// indices are integers that name an existing v, vt or vn (negative ones counting back from the
// line); mtllib names .mtl files (mtlPath()). A binary file throws
// `<where>invalid OBJ "<file>": not a text OBJ file (byte 0xNN at offset K)`.
void checkObjText(const std::string& text, const std::filesystem::path& file, const std::string& where);

// The MTL `text` of `file`: it is text, and its Kd and Ke lines hold 3 numbers that fit a float.
void checkMtlText(const std::string& text, const std::filesystem::path& file, const std::string& where);

// The MTL file that mtllib `name` of an OBJ in `folder` names.
std::filesystem::path mtlPath(const std::filesystem::path& folder, const std::string& name);

}  // namespace gibench
