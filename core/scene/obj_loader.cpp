#include "core/scene/obj_loader.h"

#include "core/config/input_file.h"
#include "core/scene/obj_text.h"
#include "core/util/error.h"

#include <tiny_obj_loader.h>

#include <map>
#include <sstream>
#include <unordered_map>

namespace gibench {
namespace {

// Opens each mtllib file itself, so the loader knows which files were read and which material
// came from which file, and a missing MTL is an error instead of tinyobjloader's silent default.
class MtlReader : public tinyobj::MaterialReader {
public:
    MtlReader(std::filesystem::path folder, std::string where) : m_folder(std::move(folder)), m_where(std::move(where)) {}

    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials, std::map<std::string, int>* names,
                    std::string* warning, std::string* error) override {
        const std::filesystem::path file = mtlPath(m_folder, name);
        std::string text;
        try {
            text = readInputFile(file, "");
        } catch (const InputError& e) {
            m_missing.push_back({file, e.what()});
            return false;
        }
        checkMtlText(text, file, m_where);
        std::istringstream in(text);
        std::string mtlWarning;
        tinyobj::LoadMtl(names, materials, &in, &mtlWarning, error);
        *warning += mtlWarning;
        m_files.push_back(file);
        m_sourceOf.resize(materials->size(), file);
        return true;
    }

    struct Missing {
        std::filesystem::path file;
        std::string reason;
    };
    const std::vector<Missing>& missing() const { return m_missing; }
    const std::vector<std::filesystem::path>& files() const { return m_files; }
    // The MTL file that defined material `index`.
    const std::filesystem::path& sourceOf(std::size_t index) const { return m_sourceOf[index]; }

private:
    std::filesystem::path m_folder;
    std::string m_where;
    std::vector<Missing> m_missing;
    std::vector<std::filesystem::path> m_files;
    std::vector<std::filesystem::path> m_sourceOf;
};

// One InputError line per message line; tinyobjloader ends some messages with a stray "."
// line, which says nothing.
[[noreturn]] void throwMessages(const std::string& prefix, const std::string& messages) {
    std::string out;
    std::istringstream lines(messages);
    for (std::string line; std::getline(lines, line);) {
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos) continue;
        line = line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
        if (line == ".") continue;
        out += (out.empty() ? "" : "\n") + prefix + line;
    }
    throw InputError(out.empty() ? prefix + "unknown problem" : out);
}

struct CornerKey {
    int position, normal, uv;
    bool operator==(const CornerKey&) const = default;
};

struct CornerHash {
    std::size_t operator()(const CornerKey& k) const {
        std::size_t h = std::hash<int>()(k.position);
        h = h * 0x9E3779B97F4A7C15ull + std::hash<int>()(k.normal);
        return h * 0x9E3779B97F4A7C15ull + std::hash<int>()(k.uv);
    }
};

// A zero (or non-finite) normal gets the area-weighted normal of its faces.
void repairNormals(Mesh& mesh) {
    std::vector<bool> broken(mesh.normals.size());
    bool any = false;
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        const float length = glm::length(mesh.normals[i]);
        broken[i] = !(length > 0.0f) || !std::isfinite(length);
        any = any || broken[i];
        if (!broken[i]) mesh.normals[i] /= length;
    }
    if (!any) return;
    std::vector<vec3> sum(mesh.normals.size(), vec3(0.0f));
    for (const uvec3& t : mesh.indices) {
        const vec3 n = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
        for (uint32_t v : {t.x, t.y, t.z})
            if (broken[v]) sum[v] += n;
    }
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        if (!broken[i]) continue;
        // A vertex of degenerate faces only is never hit, so any unit normal serves.
        const float length = glm::length(sum[i]);
        mesh.normals[i] = length > 0.0f ? sum[i] / length : vec3(0.0f, 0.0f, 1.0f);
    }
}

Mesh convertShape(const tinyobj::shape_t& shape, const tinyobj::attrib_t& attrib, const std::string& prefix) {
    const auto& corners = shape.mesh.indices;
    bool hasNormals = true, hasUvs = true;
    for (const tinyobj::index_t& c : corners) {
        hasNormals = hasNormals && c.normal_index >= 0;
        hasUvs = hasUvs && c.texcoord_index >= 0;
    }
    const auto positionCount = static_cast<int>(attrib.vertices.size() / 3);
    const auto normalCount = static_cast<int>(attrib.normals.size() / 3);
    const auto uvCount = static_cast<int>(attrib.texcoords.size() / 2);

    Mesh mesh;
    mesh.name = shape.name;
    mesh.indices.reserve(shape.mesh.num_face_vertices.size());
    mesh.materials.reserve(shape.mesh.num_face_vertices.size());
    std::unordered_map<CornerKey, uint32_t, CornerHash> vertexOf;
    auto vertex = [&](const tinyobj::index_t& c) {
        const CornerKey key{c.vertex_index, hasNormals ? c.normal_index : -1, hasUvs ? c.texcoord_index : -1};
        // tinyobjloader reports indices past the end as a warning only and still returns them.
        if (key.position < 0 || key.position >= positionCount || key.normal >= normalCount || key.uv >= uvCount)
            throw InputError(prefix + "group \"" + shape.name + "\" has a face corner with an index out of range");
        auto [it, added] = vertexOf.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
        if (added) {
            const float* p = &attrib.vertices[3 * std::size_t(key.position)];
            mesh.positions.emplace_back(p[0], p[1], p[2]);
            if (hasNormals) {
                const float* n = &attrib.normals[3 * std::size_t(key.normal)];
                mesh.normals.emplace_back(n[0], n[1], n[2]);
            }
            if (hasUvs) {
                const float* t = &attrib.texcoords[2 * std::size_t(key.uv)];
                mesh.uvs.emplace_back(t[0], t[1]);
            }
        }
        return it->second;
    };

    std::size_t offset = 0;
    for (std::size_t face = 0; face < shape.mesh.num_face_vertices.size(); ++face) {
        const unsigned count = shape.mesh.num_face_vertices[face];
        if (count != 3)
            throw InputError(prefix + "group \"" + shape.name + "\" has a face of " + std::to_string(count) +
                             " vertices after triangulation");
        mesh.indices.emplace_back(vertex(corners[offset]), vertex(corners[offset + 1]), vertex(corners[offset + 2]));
        const int material = shape.mesh.material_ids[face];
        mesh.materials.push_back(material < 0 ? kNoObjMaterial : static_cast<uint32_t>(material));
        offset += count;
    }
    repairNormals(mesh);
    return mesh;
}

}  // namespace

ObjModel readObj(const std::filesystem::path& file, const std::string& where) {
    const std::string text = readInputFile(file, where + "cannot read OBJ \"" + file.string() + "\": ");
    checkObjText(text, file, where);
    std::istringstream in(text);

    MtlReader mtlReader(file.parent_path(), where);
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warning, error;
    const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &error, &in, &mtlReader, true, false);

    if (!mtlReader.missing().empty()) {
        const auto& m = mtlReader.missing().front();
        throw InputError(where + "cannot read MTL \"" + m.file.string() + "\" named by \"" + file.string() + "\": " + m.reason);
    }
    const std::string invalid = where + "invalid OBJ \"" + file.string() + "\": ";
    if (!ok || !error.empty() || !warning.empty()) throwMessages(invalid, error + warning);

    ObjModel model;
    model.files.push_back(file);
    model.files.insert(model.files.end(), mtlReader.files().begin(), mtlReader.files().end());
    for (std::size_t i = 0; i < materials.size(); ++i) {
        const tinyobj::material_t& m = materials[i];
        ObjMaterial out;
        out.name = m.name;
        out.diffuse = Color(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
        out.emission = Color(m.emission[0], m.emission[1], m.emission[2]);
        out.mtlFile = mtlReader.sourceOf(i);
        if (!m.diffuse_texname.empty()) out.diffuseTexture = (out.mtlFile.parent_path() / m.diffuse_texname).lexically_normal();
        model.materials.push_back(std::move(out));
    }
    std::size_t triangles = 0, degenerate = 0;
    for (const tinyobj::shape_t& shape : shapes) {
        if (shape.mesh.indices.empty()) continue;
        model.meshes.push_back(convertShape(shape, attrib, invalid));
        const Mesh& mesh = model.meshes.back();
        triangles += mesh.triangleCount();
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) degenerate += hasZeroArea(mesh, t);
    }
    // A model that renders as nothing is a wrong file, not an empty scene.
    if (triangles == 0) throw InputError(invalid + "no faces");
    if (degenerate == triangles)
        throw InputError(invalid + "all " + std::to_string(triangles) + " triangles are degenerate (zero area)");
    return model;
}

}  // namespace gibench
