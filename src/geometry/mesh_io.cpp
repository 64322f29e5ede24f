#include "jade/geometry/mesh_io.h"

#include "jade/core/error.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <unordered_map>

namespace jade {

namespace {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

// tinyobjloader reads a coordinate it cannot parse ("nan", "inf", "1e999"
// overflows aside) as 0, silently; its vertex lines are parsed again here
// with strtof, which knows those words, so that they are refused instead.
void check_obj_coordinates(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    for (long number = 1; std::getline(in, line); ++number) {
        const std::size_t at = line.find_first_not_of(" \t");  // OBJ allows leading blanks
        if (at == std::string::npos || line.size() < at + 2 || line[at] != 'v' ||
            (line[at + 1] != ' ' && line[at + 1] != '\t'))
            continue;
        const char* p = line.c_str() + at + 1;
        for (int k = 0; k < 3; ++k) {
            char* end = nullptr;
            const float v = std::strtof(p, &end);
            if (end == p)
                fail_file(path, "line " + std::to_string(number) + ": a vertex needs three numbers");
            if (!std::isfinite(v))
                fail_file(path, "line " + std::to_string(number) + ": a NaN or infinite vertex coordinate");
            p = end;
        }
    }
}

TriangleMesh load_obj(const std::string& path) {
    check_obj_coordinates(path);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = "";  // materials are not ours to read
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config))
        fail_file(path, "cannot read as OBJ (" + reader.Error() + ")");
    const auto& attrib = reader.GetAttrib();
    TriangleMesh mesh;
    // Normals are used only when every face corner has one.
    bool all_normals = !attrib.normals.empty();
    for (const auto& shape : reader.GetShapes())
        for (const auto& idx : shape.mesh.indices) all_normals = all_normals && idx.normal_index >= 0;
    // One vertex per distinct (position, normal) pair.
    std::map<std::pair<int, int>, std::uint32_t> vertex_of;
    for (const auto& shape : reader.GetShapes()) {
        const auto& idx = shape.mesh.indices;
        for (std::size_t f = 0; f + 2 < idx.size(); f += 3) {
            std::array<std::uint32_t, 3> tri{};
            for (int k = 0; k < 3; ++k) {
                const int vi = idx[f + k].vertex_index, ni = all_normals ? idx[f + k].normal_index : -1;
                if (vi < 0 || std::size_t(3 * vi + 2) >= attrib.vertices.size())
                    fail_file(path, "a face refers to a vertex that does not exist");
                auto [it, fresh] = vertex_of.try_emplace({vi, ni}, std::uint32_t(mesh.positions.size()));
                if (fresh) {
                    mesh.positions.emplace_back(attrib.vertices[3 * vi], attrib.vertices[3 * vi + 1],
                                                attrib.vertices[3 * vi + 2]);
                    if (all_normals)
                        mesh.normals.emplace_back(attrib.normals[3 * ni], attrib.normals[3 * ni + 1],
                                                  attrib.normals[3 * ni + 2]);
                }
                tri[k] = it->second;
            }
            mesh.triangles.push_back(tri);
        }
    }
    mesh.file_normals = all_normals;
    return mesh;
}

glm::mat4 node_matrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        glm::dmat4 m;
        std::memcpy(glm::value_ptr(m), node.matrix.data(), 16 * sizeof(double));
        return glm::mat4(m);
    }
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3)
        m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4)  // glTF stores x, y, z, w
        m = m * glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1],
                                          node.rotation[2]));
    if (node.scale.size() == 3)
        m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return glm::mat4(m);
}

// Reads element i of a float vec3 accessor, or an index of any integer width.
struct AccessorView {
    const unsigned char* data = nullptr;
    std::size_t stride = 0, count = 0;
    int component = 0;
};

AccessorView view_of(const tinygltf::Model& model, int accessor_index, const std::string& path) {
    if (accessor_index < 0 || std::size_t(accessor_index) >= model.accessors.size())
        fail_file(path, "a primitive refers to a missing accessor");
    const auto& acc = model.accessors[accessor_index];
    if (acc.bufferView < 0) fail_file(path, "sparse or empty accessors are not supported");
    const auto& bv = model.bufferViews[acc.bufferView];
    const auto& buf = model.buffers[bv.buffer];
    AccessorView v;
    v.component = acc.componentType;
    v.count = acc.count;
    const std::size_t elem = std::size_t(tinygltf::GetComponentSizeInBytes(acc.componentType)) *
                             std::size_t(tinygltf::GetNumComponentsInType(acc.type));
    v.stride = bv.byteStride ? bv.byteStride : elem;
    const std::size_t start = bv.byteOffset + acc.byteOffset;
    if (acc.count > 0 && start + v.stride * (acc.count - 1) + elem > buf.data.size())
        fail_file(path, "an accessor reaches past the end of its buffer");
    v.data = buf.data.data() + start;
    return v;
}

std::uint32_t index_at(const AccessorView& v, std::size_t i) {
    const unsigned char* p = v.data + i * v.stride;
    switch (v.component) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t x; std::memcpy(&x, p, 2); return x; }
        default: { std::uint32_t x; std::memcpy(&x, p, 4); return x; }
    }
}

glm::vec3 vec3_at(const AccessorView& v, std::size_t i) {
    float f[3];
    std::memcpy(f, v.data + i * v.stride, sizeof f);
    return {f[0], f[1], f[2]};
}

tinygltf::Model read_gltf_model(const std::string& path);

// Calls visit(node, world transform) for every node of the default scene
// (every node when the file has no scene), parents before children.
void for_each_scene_node(const tinygltf::Model& model,
                         const std::function<void(const tinygltf::Node&, const glm::mat4&)>& visit) {
    auto walk = [&](auto&& self, int index, const glm::mat4& parent) -> void {
        const auto& node = model.nodes[std::size_t(index)];
        const glm::mat4 world = parent * node_matrix(node);
        visit(node, world);
        for (int child : node.children) self(self, child, world);
    };
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (!model.scenes.empty())
        for (int root : model.scenes[std::size_t(scene)].nodes) walk(walk, root, glm::mat4(1.f));
    else
        for (std::size_t i = 0; i < model.nodes.size(); ++i) walk(walk, int(i), glm::mat4(1.f));
}

TriangleMesh load_gltf(const std::string& path) {
    const tinygltf::Model model = read_gltf_model(path);

    TriangleMesh mesh;
    bool all_normals = true;
    std::vector<glm::vec3> normals;
    for_each_scene_node(model, [&](const tinygltf::Node& node, const glm::mat4& world) {
        const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(world)));
        if (node.mesh >= 0)
            for (const auto& prim : model.meshes[node.mesh].primitives) {
                if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;
                const auto pos_it = prim.attributes.find("POSITION");
                if (pos_it == prim.attributes.end()) continue;
                const AccessorView pos = view_of(model, pos_it->second, path);
                if (model.accessors[pos_it->second].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
                    fail_file(path, "POSITION must be float");
                const auto nrm_it = prim.attributes.find("NORMAL");
                const bool has_n = nrm_it != prim.attributes.end();
                all_normals = all_normals && has_n;
                const std::uint32_t base = std::uint32_t(mesh.positions.size());
                for (std::size_t i = 0; i < pos.count; ++i)
                    mesh.positions.push_back(glm::vec3(world * glm::vec4(vec3_at(pos, i), 1.f)));
                if (has_n) {
                    const AccessorView n = view_of(model, nrm_it->second, path);
                    for (std::size_t i = 0; i < n.count; ++i)
                        normals.push_back(glm::normalize(normal_matrix * vec3_at(n, i)));
                }
                std::vector<std::uint32_t> idx;
                if (prim.indices >= 0) {
                    const AccessorView iv = view_of(model, prim.indices, path);
                    for (std::size_t i = 0; i < iv.count; ++i) idx.push_back(index_at(iv, i));
                } else {
                    for (std::size_t i = 0; i < pos.count; ++i) idx.push_back(std::uint32_t(i));
                }
                // A mirroring transform flips the winding; keep triangles outward.
                const bool flip = glm::determinant(glm::mat3(world)) < 0.f;
                for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
                    for (int k = 0; k < 3; ++k)
                        if (idx[i + k] >= pos.count) fail_file(path, "an index points past the vertices");
                    mesh.triangles.push_back(flip ? std::array<std::uint32_t, 3>{base + idx[i], base + idx[i + 2], base + idx[i + 1]}
                                                  : std::array<std::uint32_t, 3>{base + idx[i], base + idx[i + 1], base + idx[i + 2]});
                }
            }
    });
    if (all_normals && normals.size() == mesh.positions.size()) {
        mesh.normals = std::move(normals);
        mesh.file_normals = true;
    }
    return mesh;
}

tinygltf::Model read_gltf_model(const std::string& path) {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool ok = lower_extension(path) == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                                    : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) fail_file(path, "cannot read as glTF (" + err + ")");
    return model;
}

}  // namespace

TriangleMesh load_mesh(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail_file(path, "no such file");
    const std::string ext = lower_extension(path);
    TriangleMesh mesh;
    if (ext == ".obj")
        mesh = load_obj(path);
    else if (ext == ".gltf" || ext == ".glb")
        mesh = load_gltf(path);
    else
        fail_file(path, "unknown mesh format '" + ext + "' (use .obj, .gltf or .glb)");
    mesh.path = path;
    validate_mesh(mesh);
    if (mesh.file_normals)
        for (auto& n : mesh.normals) {
            const float len = glm::length(n);
            n = len > 0.f && std::isfinite(len) ? n / len : glm::vec3(0.f);
        }
    if (!mesh.file_normals) compute_vertex_normals(mesh);
    return mesh;
}

void validate_mesh(const TriangleMesh& mesh) {
    if (mesh.triangles.empty()) fail_file(mesh.path, "the mesh has no triangle");
    float reach = 0.f;
    for (const auto& p : mesh.positions) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            fail_file(mesh.path, "the mesh has a NaN or infinite vertex coordinate");
        reach = std::max({reach, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    }
    const glm::vec3 e = mesh.bounds().extent();
    const float size = std::max({e.x, e.y, e.z});
    if (size <= 0.f) fail_file(mesh.path, "the mesh has zero size");
    bool any_area = false;
    for (std::size_t t = 0; t < mesh.triangles.size() && !any_area; ++t)
        any_area = glm::length(mesh.face_normal(t)) > 0.f;
    if (!any_area) fail_file(mesh.path, "every triangle of the mesh is degenerate (zero area)");
    std::ostringstream size_text;
    size_text << size;
    if (size < kMinMeshSize || size > kMaxMeshSize)
        fail_file(mesh.path, "the mesh is " + size_text.str() +
                                 " units across; rescale it to between 1e-6 and 1e7 (single-precision "
                                 "ray tracing loses it outside that range)");
    if (size < kMinMeshSizePerReach * reach)
        fail_file(mesh.path, "the mesh is " + size_text.str() +
                                 " units across but lies far from the origin; move it toward the origin "
                                 "(single precision cannot resolve it there)");
}

namespace {

// The glTF scene a camera or a light is read from (`what` names it in the
// message when the file is not glTF).
tinygltf::Model read_gltf_scene_for(const std::string& path, const char* what) {
    const std::string ext = lower_extension(path);
    if (ext != ".gltf" && ext != ".glb") fail_file(path, std::string(what) + " can be read from .gltf or .glb only");
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail_file(path, "no such file");
    return read_gltf_model(path);
}

}  // namespace

FileCamera load_gltf_camera(const std::string& path) {
    const tinygltf::Model model = read_gltf_scene_for(path, "a camera");
    std::optional<FileCamera> found;
    for_each_scene_node(model, [&](const tinygltf::Node& node, const glm::mat4& world) {
        if (found) return;
        if (node.camera >= 0 && model.cameras[std::size_t(node.camera)].type == "perspective") {
            FileCamera c;
            c.origin = glm::vec3(world * glm::vec4(0.f, 0.f, 0.f, 1.f));
            c.forward = glm::normalize(glm::vec3(world * glm::vec4(0.f, 0.f, -1.f, 0.f)));
            c.up = glm::normalize(glm::vec3(world * glm::vec4(0.f, 1.f, 0.f, 0.f)));
            c.yfov_radians = float(model.cameras[std::size_t(node.camera)].perspective.yfov);
            found = c;
        }
    });
    if (!found) fail_file(path, "holds no perspective camera");
    if (!(found->yfov_radians > 0.f && found->yfov_radians < 3.14f))
        fail_file(path, "its camera's yfov is not between 0 and pi");
    return *found;
}

namespace {

// The KHR_lights_punctual light a node carries, -1 for none.
int node_light(const tinygltf::Node& node) {
    const auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end() || !ext->second.IsObject() || !ext->second.Has("light")) return -1;
    const tinygltf::Value& index = ext->second.Get("light");
    return index.IsNumber() ? index.GetNumberAsInt() : -1;
}

}  // namespace

FileLight load_gltf_directional_light(const std::string& path) {
    const tinygltf::Model model = read_gltf_scene_for(path, "a light");
    std::optional<FileLight> found;
    for_each_scene_node(model, [&](const tinygltf::Node& node, const glm::mat4& world) {
        const int index = node_light(node);
        if (found || index < 0 || std::size_t(index) >= model.lights.size()) return;
        const tinygltf::Light& light = model.lights[std::size_t(index)];
        if (light.type != "directional") return;
        FileLight f;
        f.name = light.name;
        const glm::vec3 z(world * glm::vec4(0.f, 0.f, 1.f, 0.f));
        f.toward = glm::length(z) > 0.f ? glm::normalize(z) : glm::vec3(0.f);
        std::array<double, 3> colour{1, 1, 1};
        if (light.color.size() == 3) colour = {light.color[0], light.color[1], light.color[2]};
        f.irradiance = float(light.intensity * (colour[0] + colour[1] + colour[2]) / 3.0);
        f.coloured = colour[0] != colour[1] || colour[1] != colour[2];
        found = f;
    });
    if (!found) fail_file(path, "holds no directional light (KHR_lights_punctual)");
    if (!(glm::length(found->toward) > 0.f) || !std::isfinite(found->irradiance) || found->irradiance < 0.f)
        fail_file(path, "its directional light has no direction or a negative or non-finite intensity");
    return *found;
}

}  // namespace jade
