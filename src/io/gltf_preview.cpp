#include "jade/io/gltf_preview.h"

#include "jade/core/error.h"
#include "jade/io/atomic_file.h"
#include "jade/volume/slab_reflectance.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace jade {

namespace {

// The smallest attenuation written: viewers take its logarithm.
constexpr double kMinAttenuation = 1.0 / 1024.0;

using tinygltf::Value;

Value number_array(const std::array<double, 3>& v) {
    return Value(Value::Array{Value(v[0]), Value(v[1]), Value(v[2])});
}

Value extension(const char* key, Value value) {
    Value::Object o;
    o[key] = std::move(value);
    return Value(std::move(o));
}

// Appends `bytes` to the model's one buffer as a new buffer view; returns its index.
int add_view(tinygltf::Model& model, const void* bytes, std::size_t size, int target) {
    std::vector<unsigned char>& data = model.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = size;
    view.target = target;
    data.resize(data.size() + size);
    std::memcpy(data.data() + view.byteOffset, bytes, size);
    model.bufferViews.push_back(view);
    return int(model.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& model, int view, int component, int type, std::size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.type = type;
    a.count = count;
    model.accessors.push_back(a);
    return int(model.accessors.size()) - 1;
}

tinygltf::Material material_of(const GltfPreviewMaterial& m) {
    tinygltf::Material mat;
    mat.name = "jaderender preview";
    mat.pbrMetallicRoughness.baseColorFactor = {m.base_color[0], m.base_color[1], m.base_color[2], 1.0};
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = 0.0;  // the boundary is smooth (paper §5.3)
    mat.extensions["KHR_materials_transmission"] = extension("transmissionFactor", Value(m.transmission));
    Value::Object volume;
    volume["thicknessFactor"] = Value(m.thickness);
    volume["attenuationDistance"] = Value(m.attenuation_distance);
    volume["attenuationColor"] = number_array(m.attenuation_color);
    mat.extensions["KHR_materials_volume"] = Value(std::move(volume));
    mat.extensions["KHR_materials_ior"] = extension("ior", Value(m.ior));
    Value::Object extras;
    extras["jade:sigma_s"] = number_array(m.sigma_s);
    extras["jade:sigma_a"] = number_array(m.sigma_a);
    extras["jade:g"] = Value(m.g);
    extras["jade:slab_reflectance"] = number_array(m.slab_R);
    extras["jade:slab_transmittance"] = number_array(m.slab_T);
    mat.extras = Value(std::move(extras));
    return mat;
}

}  // namespace

GltfPreviewMaterial gltf_preview_material(const std::array<double, 3>& sigma_s,
                                          const std::array<double, 3>& sigma_a, double g, double ior,
                                          double thickness) {
    if (!(thickness > 0.0) || !std::isfinite(thickness))
        throw Error("the preview's thickness must be positive and finite");
    GltfPreviewMaterial m;
    m.sigma_s = sigma_s;
    m.sigma_a = sigma_a;
    m.g = g;
    m.ior = ior;
    m.thickness = m.attenuation_distance = thickness;
    m.transmission = 0.0;
    for (int c = 0; c < 3; ++c) {
        const SlabReflectance slab =
            kubelka_munk_slab(kubelka_munk_coefficients(sigma_s[c], sigma_a[c], g), thickness);
        m.slab_R[c] = slab.R;
        m.slab_T[c] = slab.T;
        if (slab.R + slab.T > 0.0) m.transmission = std::max(m.transmission, slab.T / (slab.R + slab.T));
    }
    const double t = m.transmission;
    for (int c = 0; c < 3; ++c) {
        m.base_color[c] = t < 1.0 ? std::min(1.0, m.slab_R[c] / (1.0 - t)) : 1.0;
        m.attenuation_color[c] = t > 0.0 && m.base_color[c] > 0.0
                                     ? std::clamp(m.slab_T[c] / (t * m.base_color[c]), kMinAttenuation, 1.0)
                                     : 1.0;
    }
    return m;
}

void write_preview_glb(const std::string& path, const TriangleMesh& mesh, const GltfPreviewMaterial& material) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "jaderender";
    model.buffers.resize(1);
    model.extensionsUsed = {"KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"};

    const int positions = add_accessor(
        model, add_view(model, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3), TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, mesh.positions.size());
    const Bounds3 box = mesh.bounds();
    model.accessors[positions].minValues = {box.min.x, box.min.y, box.min.z};
    model.accessors[positions].maxValues = {box.max.x, box.max.y, box.max.z};
    const int normals = add_accessor(
        model, add_view(model, mesh.normals.data(), mesh.normals.size() * sizeof(glm::vec3), TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, mesh.normals.size());
    const int indices = add_accessor(
        model,
        add_view(model, mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]),
                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, mesh.triangles.size() * 3);

    model.materials.push_back(material_of(material));
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = positions;
    prim.attributes["NORMAL"] = normals;
    prim.indices = indices;
    prim.material = 0;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Mesh gmesh;
    gmesh.name = "object";
    gmesh.primitives.push_back(prim);
    model.meshes.push_back(gmesh);
    tinygltf::Node node;
    node.mesh = 0;
    node.name = "object";
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes = {0};
    model.scenes.push_back(scene);
    model.defaultScene = 0;

    std::ostringstream bytes;
    if (!tinygltf::TinyGLTF().WriteGltfSceneToStream(&model, bytes, false, true))
        fail_file(path, "cannot encode the glTF preview");
    write_text_file(path, bytes.str());
}

}  // namespace jade
