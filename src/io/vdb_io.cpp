#include "jade/io/vdb_io.h"

#include "jade/io/atomic_file.h"
#include "jade/io/vdb_check.h"
#include "jade/core/error.h"
#include "jade/core/memory.h"
#include "jade/core/subprocess.h"

#include <glm/common.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/Prune.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cmath>
#include <limits>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

namespace jade {

namespace {

// A damaged grid can ask for more memory than exists (a size read past the
// file's end): refused like any damage.
[[noreturn]] void fail_vdb_too_large(const std::string& path) {
    fail_file(path, "damaged or cut short: a grid asks for more memory than a file of its size can hold");
}

constexpr const char* kFormat = "jaderender material volume";
// 1: levels recovered from sigma_s/sigma_a over the whole cube. 2: the
// levels in a grid of their own, the coefficient grids possibly masked to the
// mesh and rotated Z-up.
constexpr int kFormatVersion = 2;

// One leaf origin per 8^3 block of the cube.
std::vector<openvdb::Coord> leaf_origins(int s) {
    std::vector<openvdb::Coord> origins;
    for (int z = 0; z < s; z += 8)
        for (int y = 0; y < s; y += 8)
            for (int x = 0; x < s; x += 8) origins.emplace_back(x, y, z);
    return origins;
}

template <typename GridT>
typename GridT::Ptr make_grid(const std::string& name, const std::string& units, const std::string& description,
                              const openvdb::math::Transform::Ptr& xform, const std::vector<openvdb::Coord>& origins,
                              std::vector<typename GridT::TreeType::LeafNodeType*>& leaves) {
    auto grid = GridT::create(typename GridT::ValueType(0));
    grid->setName(name);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    // Grid-level metadata, for a user who opens the file in another tool.
    grid->insertMeta("units", openvdb::StringMetadata(units));
    grid->insertMeta("description", openvdb::StringMetadata(description));
    grid->setTransform(xform);
    leaves.resize(origins.size());
    for (std::size_t i = 0; i < origins.size(); ++i) leaves[i] = grid->tree().touchLeaf(origins[i]);
    return grid;
}

openvdb::math::Transform::Ptr cube_transform(const MaterialVolume& v, bool z_up) {
    const double h = v.voxel_size();
    auto xform = openvdb::math::Transform::createLinearTransform(h);
    xform->postTranslate(openvdb::Vec3d(v.cube.min[0] + 0.5 * h, v.cube.min[1] + 0.5 * h,
                                        v.cube.min[2] + 0.5 * h));
    // Y-up world → Z-up world: (x, y, z) → (x, −z, y), +90° about x, the
    // turn Blender's glTF importer gives the mesh.
    if (z_up) xform->postRotate(0.5 * M_PI, openvdb::math::X_AXIS);
    return xform;
}

// Where `mesh` lies on the volume's grid: the voxels inside it grown by one
// voxel, so that interpolation anywhere inside the surface reads coefficients
// rather than the empty background, and the signed distance to the surface on
// them (OpenVDB's mesh-to-level-set; negative inside). A renderer that
// interpolates the grids (Cycles, Houdini) cuts the grown shell off at the
// surface by the distance's sign, to a fraction of a voxel; without the shell
// the surface's last half voxel would fade, and with it uncut it would show as
// stone outside the surface (docs/blender.md measures both).
struct MeshMask {
    openvdb::BoolGrid::Ptr voxels;
    openvdb::FloatGrid::Ptr distance;
};

MeshMask mesh_mask(const MaterialVolume& v, const TriangleMesh& mesh) {
    const auto xform = cube_transform(v, false);
    std::vector<openvdb::Vec3s> points;
    points.reserve(mesh.positions.size());
    for (const glm::vec3& p : mesh.positions) points.emplace_back(p.x, p.y, p.z);
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
    MeshMask m;
    m.distance = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, triangles, 3.f);
    m.voxels = openvdb::tools::sdfInteriorMask(*m.distance);
    openvdb::tools::dilateActiveValues(m.voxels->tree(), 1, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                       openvdb::tools::EXPAND_TILES);
    return m;
}

// The leaves of the cube that hold a voxel of the mask (all with none).
std::vector<openvdb::Coord> masked_origins(const std::vector<openvdb::Coord>& origins, const openvdb::BoolGrid* mask) {
    if (!mask) return origins;
    std::vector<openvdb::Coord> kept;
    const auto& tree = mask->tree();
    for (const openvdb::Coord& o : origins) {
        const auto* leaf = tree.probeConstLeaf(o);
        if (leaf ? !leaf->isEmpty() : tree.isValueOn(o)) kept.push_back(o);
    }
    return kept;
}

// The four coefficient grids of a material volume (docs/design.md, "The .vdb
// file"), filled from its levels; only the voxels of `mask` when one is given.
openvdb::GridPtrVec coefficient_grids(const MaterialVolume& v, const openvdb::BoolGrid* mask, bool z_up,
                                      const std::string& color_name) {
    const int s = v.resolution;
    const auto xform = cube_transform(v, z_up);
    const auto origins = masked_origins(leaf_origins(s), mask);
    std::vector<openvdb::Vec3fGrid::TreeType::LeafNodeType*> ls, la, lc;
    std::vector<openvdb::FloatGrid::TreeType::LeafNodeType*> ld;
    auto sigma_s = make_grid<openvdb::Vec3fGrid>("sigma_s", "1/world unit",
                                                 "scattering coefficient, RGB", xform, origins, ls);
    auto sigma_a = make_grid<openvdb::Vec3fGrid>("sigma_a", "1/world unit",
                                                 "absorption coefficient, RGB", xform, origins, la);
    auto density = make_grid<openvdb::FloatGrid>(
        "density", "1/world unit", "extinction sigma_s + sigma_a, mean of RGB", xform, origins, ld);
    auto color = make_grid<openvdb::Vec3fGrid>(color_name, "none", "single-scattering albedo sigma_s / sigma_t, RGB",
                                               xform, origins, lc);

    const CoefficientTable table(v.optics, v.cube.side);
    tbb::parallel_for(std::size_t(0), origins.size(), [&](std::size_t li) {
        const openvdb::Coord o = origins[li];
        auto inside = mask ? std::make_unique<openvdb::BoolGrid::ConstAccessor>(mask->getConstAccessor()) : nullptr;
        // x innermost: the levels are stored x fastest.
        for (int z = o.z(); z < std::min(o.z() + 8, s); ++z)
            for (int y = o.y(); y < std::min(o.y() + 8, s); ++y)
                for (int x = o.x(); x < std::min(o.x() + 8, s); ++x) {
                    if (inside && !inside->isValueOn(openvdb::Coord(x, y, z))) continue;
                    const Rgb8 lv = v.levels[v.index(x, y, z)];
                    openvdb::Vec3f ss, sa, albedo;
                    for (int c = 0; c < 3; ++c) {
                        ss[c] = table.sigma_s[c][lv[c]];
                        sa[c] = table.sigma_a[c][lv[c]];
                        const float st = ss[c] + sa[c];
                        albedo[c] = st > 0.f ? ss[c] / st : 0.f;
                    }
                    const float mean_st = (ss[0] + sa[0] + ss[1] + sa[1] + ss[2] + sa[2]) / 3.f;
                    const auto off = openvdb::Vec3fGrid::TreeType::LeafNodeType::coordToOffset(
                        openvdb::Coord(x, y, z));
                    ls[li]->setValueOn(off, ss);
                    la[li]->setValueOn(off, sa);
                    lc[li]->setValueOn(off, albedo);
                    ld[li]->setValueOn(off, mean_st);
                }
    });
    return {density, color, sigma_s, sigma_a};
}

// The mesh's signed distance on the voxels of the masked coefficient grids
// (world units, negative inside): `sigma x (surface_distance < 0)` cuts their
// grown shell off at the surface.
constexpr const char* kSurfaceDistanceGrid = "surface_distance";
openvdb::FloatGrid::Ptr surface_distance_grid(const MaterialVolume& v, const MeshMask& mask, bool z_up) {
    const auto origins = masked_origins(leaf_origins(v.resolution), mask.voxels.get());
    std::vector<openvdb::FloatGrid::TreeType::LeafNodeType*> leaves;
    auto grid = make_grid<openvdb::FloatGrid>(kSurfaceDistanceGrid, "world unit",
                                              "signed distance to the mesh, negative inside", cube_transform(v, z_up),
                                              origins, leaves);
    tbb::parallel_for(std::size_t(0), origins.size(), [&](std::size_t li) {
        const auto inside = mask.voxels->getConstAccessor();
        const auto distance = mask.distance->getConstAccessor();
        for (auto it = leaves[li]->beginValueAll(); it; ++it) {
            const openvdb::Coord xyz = it.getCoord();
            if (inside.isValueOn(xyz)) leaves[li]->setValueOn(it.pos(), distance.getValue(xyz));
        }
    });
    return grid;
}

// The levels themselves, every voxel of the cube (the material is the whole
// cube; a mesh only carves it), packed r | g << 8 | b << 16 in an Int32 grid
// (OpenVDB has no 3-byte type): what jaderender reads back, exactly and
// without inverting coefficients.
constexpr const char* kLevelsGrid = "levels";
openvdb::Int32Grid::Ptr levels_grid(const MaterialVolume& v, bool z_up) {
    const int s = v.resolution;
    const auto origins = leaf_origins(s);
    std::vector<openvdb::Int32Grid::TreeType::LeafNodeType*> leaves;
    auto grid = make_grid<openvdb::Int32Grid>(kLevelsGrid, "none",
                                              "the material's 8-bit levels, r | g << 8 | b << 16 (jaderender)",
                                              cube_transform(v, z_up), origins, leaves);
    grid->setGridClass(openvdb::GRID_UNKNOWN);
    tbb::parallel_for(std::size_t(0), origins.size(), [&](std::size_t li) {
        const openvdb::Coord o = origins[li];
        for (int z = o.z(); z < std::min(o.z() + 8, s); ++z)
            for (int y = o.y(); y < std::min(o.y() + 8, s); ++y)
                for (int x = o.x(); x < std::min(o.x() + 8, s); ++x) {
                    const Rgb8 l = v.levels[v.index(x, y, z)];
                    leaves[li]->setValueOn(openvdb::Int32Grid::TreeType::LeafNodeType::coordToOffset(
                                               openvdb::Coord(x, y, z)),
                                           std::int32_t(l[0] | (l[1] << 8) | (l[2] << 16)));
                }
    });
    return grid;
}

// A 64-bit digest of the levels (FNV-1a), written as hex beside them and
// compared when they are read back: a file damaged or cut short where
// OpenVDB reads on without complaint is then refused. Levels that give the
// same coefficients (clipped by the contrast) cannot be told apart in the
// grids, so each counts as the lowest level of its kind. Hex text, since
// other tools rewrite 64-bit integer metadata as 32-bit.
std::string levels_digest(const MaterialVolume& v) {
    const CoefficientTable table(v.optics, v.cube.side);
    std::array<std::array<std::uint8_t, 256>, 3> canonical{};
    for (int c = 0; c < 3; ++c)
        for (int l = 0; l < 256; ++l) {
            int first = l;
            while (first > 0 && table.sigma_s[c][first - 1] == table.sigma_s[c][l] &&
                   table.sigma_a[c][first - 1] == table.sigma_a[c][l])
                --first;
            canonical[c][l] = std::uint8_t(first);
        }
    std::uint64_t h = 14695981039346656037ULL;
    for (const Rgb8& l : v.levels)
        for (int c = 0; c < 3; ++c) h = (h ^ canonical[c][l[c]]) * 1099511628211ULL;
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

// Every parameter needed to rebuild and re-render the volume exactly.
openvdb::MetaMap material_metadata(const MaterialVolume& v) {
    openvdb::MetaMap meta;
    meta.insertMeta("jade:format", openvdb::StringMetadata(kFormat));
    meta.insertMeta("jade:format_version", openvdb::Int32Metadata(kFormatVersion));
    meta.insertMeta("jade:jaderender_version", openvdb::StringMetadata(JADE_VERSION));
    // The photo's file name only: a path of the machine that made the file
    // means nothing elsewhere (report.json keeps the path as given).
    meta.insertMeta("jade:photo", openvdb::StringMetadata(std::filesystem::path(v.photo).filename().string()));
    meta.insertMeta("jade:photo_span", openvdb::DoubleMetadata(v.photo_span));
    meta.insertMeta("jade:resolution", openvdb::Int32Metadata(v.resolution));
    meta.insertMeta("jade:octaves", openvdb::Int32Metadata(v.noise.octave_count()));
    meta.insertMeta("jade:k", openvdb::DoubleMetadata(v.noise.k));
    meta.insertMeta("jade:seed", openvdb::Int64Metadata(v.noise.seed));
    meta.insertMeta("jade:structure", openvdb::StringMetadata(to_string(v.structure)));
    meta.insertMeta("jade:frequency", openvdb::DoubleMetadata(v.noise.frequency));
    meta.insertMeta("jade:stretch", openvdb::DoubleMetadata(v.noise.stretch));
    meta.insertMeta("jade:angle", openvdb::DoubleMetadata(v.noise.angle));
    meta.insertMeta("jade:bands", openvdb::DoubleMetadata(v.noise.bands));
    meta.insertMeta("jade:warp", openvdb::DoubleMetadata(v.noise.warp));
    meta.insertMeta("jade:fold", openvdb::DoubleMetadata(v.noise.fold));
    meta.insertMeta("jade:veins", openvdb::Int32Metadata(v.noise.veins ? 1 : 0));
    meta.insertMeta("jade:vein_frequency", openvdb::DoubleMetadata(v.noise.vein_frequency));
    meta.insertMeta("jade:vein_width", openvdb::DoubleMetadata(v.noise.vein_width));
    meta.insertMeta("jade:layers", openvdb::Int32Metadata(v.noise.layers ? 1 : 0));
    meta.insertMeta("jade:sharpen", openvdb::DoubleMetadata(v.noise.sharpen));
    meta.insertMeta("jade:sharpen_radius", openvdb::DoubleMetadata(v.noise.sharpen_radius));
    meta.insertMeta("jade:exemplar_wander", openvdb::DoubleMetadata(v.noise.exemplar_wander));
    meta.insertMeta("jade:match", openvdb::StringMetadata(to_string(v.match)));
    meta.insertMeta("jade:extinction", openvdb::StringMetadata(to_string(v.optics.extinction)));
    meta.insertMeta("jade:ds", openvdb::DoubleMetadata(v.optics.ds));
    meta.insertMeta("jade:da", openvdb::DoubleMetadata(v.optics.da));
    meta.insertMeta("jade:ks", openvdb::Vec3DMetadata(
                                   openvdb::Vec3d(v.optics.ks[0], v.optics.ks[1], v.optics.ks[2])));
    meta.insertMeta("jade:contrast", openvdb::Vec3DMetadata(openvdb::Vec3d(
                                         v.optics.contrast[0], v.optics.contrast[1], v.optics.contrast[2])));
    meta.insertMeta("jade:mean_level", openvdb::Vec3DMetadata(openvdb::Vec3d(
                                           v.optics.mean_level[0], v.optics.mean_level[1], v.optics.mean_level[2])));
    meta.insertMeta("jade:density_scale", openvdb::DoubleMetadata(v.optics.density_scale));
    meta.insertMeta("jade:cube_min", openvdb::Vec3DMetadata(openvdb::Vec3d(
                                         v.cube.min[0], v.cube.min[1], v.cube.min[2])));
    meta.insertMeta("jade:cube_side", openvdb::DoubleMetadata(v.cube.side));
    meta.insertMeta("jade:exposure", openvdb::DoubleMetadata(v.exposure));
    meta.insertMeta("jade:levels_digest", openvdb::StringMetadata(levels_digest(v)));
    meta.insertMeta("jade:units",
                    openvdb::StringMetadata("sigma_s, sigma_a, density per world unit; "
                                            "paper coefficients x density_scale / cube_side"));
    return meta;
}

}  // namespace

namespace {
// openvdb::io::File::write neither checks its stream after writing nor
// reports a failed close: on a full disk it leaves a truncated file and
// returns normally. The same archive writer (grid offsets included, so the
// file reads back by slabs) is run here on a stream this code checks.
class CheckedVdbFile : public openvdb::io::File {
public:
    using openvdb::io::File::File;
    void write_to(std::ofstream& os, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& meta) const {
        openvdb::io::Archive::write(os, grids, /*seekable=*/true, meta);
    }
};

void write_checked(const AtomicFile& out, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& meta) {
    const std::string& temp = out.temp_path();
    CheckedVdbFile file(temp);
    // Zip rather than Blosc: zlib refuses damaged input where OpenVDB's Blosc
    // path corrupted the heap (the damaged-file test), and with the grids
    // masked to the mesh the slower writing costs under a second.
    file.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
    std::ofstream os(temp, std::ios_base::out | std::ios_base::binary | std::ios_base::trunc);
    if (!os) fail_file(out.destination(), "cannot open for writing");
    file.write_to(os, grids, meta);
    os.flush();
    const bool written = bool(os);
    os.close();
    if (!written || os.fail())
        fail_file(out.destination(), std::string("the write failed (") + std::strerror(errno) + "); is the disk full?");
}
// Whether every non-zero coefficient lies in half precision's normal range
// (6.1e-5 … 65504), where its relative error stays ≤ 2^-11.
bool fits_half(const CoefficientTable& table) {
    for (int c = 0; c < 3; ++c)
        for (const auto* t : {&table.sigma_s[c], &table.sigma_a[c]})
            for (float x : *t)
                if (x != 0.f && !(std::abs(x) >= 6.1035e-5f && std::abs(x) <= 65504.f)) return false;
    return true;
}

}  // namespace

void require_memory_for_volume(int resolution) {
    // Levels (3 bytes) + their Int32 grid (4) + sigma_s, sigma_a, color (12
    // each) + density (4), these four at most the whole cube (unmasked), and
    // a masked file's surface_distance (4).
    constexpr std::uint64_t kBytesPerVoxel =
        3 + sizeof(std::int32_t) + 3 * sizeof(openvdb::Vec3f) + 2 * sizeof(float);
    const std::uint64_t s = std::uint64_t(std::max(resolution, 0));
    require_memory(kBytesPerVoxel * s * s * s, "--resolution " + std::to_string(resolution));
}

void write_material_vdb(const std::string& path, const MaterialVolume& v, const VdbLayout& layout) {
    openvdb::initialize();
    const int s = v.resolution;
    if (s <= 0 || v.levels.size() != std::size_t(s) * s * s)
        throw Error("internal: material volume levels do not match its resolution");
    if (layout.color_name != "color" && layout.color_name != "Cd")
        throw Error("the albedo grid is named 'color' (Blender) or 'Cd' (Houdini), not '" + layout.color_name + "'");
    const MeshMask mask = layout.mask ? mesh_mask(v, *layout.mask) : MeshMask{};
    openvdb::GridPtrVec grids = coefficient_grids(v, mask.voxels.get(), layout.z_up, layout.color_name);
    if (layout.mask) grids.push_back(surface_distance_grid(v, mask, layout.z_up));
    // The levels go last: a file cut short then loses part of them, which
    // their digest reveals, instead of the end of a grid no reader here checks.
    grids.push_back(levels_grid(v, layout.z_up));
    openvdb::MetaMap meta = material_metadata(v);
    meta.insertMeta("jade:up_axis", openvdb::StringMetadata(layout.z_up ? "z" : "y"));
    meta.insertMeta("jade:masked", openvdb::StringMetadata(layout.mask ? "coefficient grids inside the mesh, "
                                                                         "grown by one voxel (cut at surface_distance "
                                                                         "< 0); levels: the whole cube"
                                                                       : "no: every voxel of the cube"));

    AtomicFile out(path);
    try {
        // Half floats for the coefficient grids (they are for other tools:
        // jaderender reads the levels grid): their relative error (<= 2^-11)
        // is far below the spacing of adjacent levels (>= 1/255 relative),
        // and the file is smaller and faster to write. Full floats where a
        // coefficient leaves half's normal range (--density-scale 1e5
        // overflowed it).
        const bool half = fits_half(CoefficientTable(v.optics, v.cube.side));
        for (const auto& g : grids) g->setSaveFloatAsHalf(half && g->getName() != kLevelsGrid);
        write_checked(out, grids, meta);
    } catch (const openvdb::Exception& e) {
        fail_file(path, std::string("cannot write OpenVDB file: ") + e.what());
    }
    out.commit();
}

namespace {

template <typename T>
T required_meta(const openvdb::MetaMap& meta, const std::string& path, const std::string& name) {
    const auto m = meta.getMetadata<openvdb::TypedMetadata<T>>(name);
    if (!m) fail_file(path, "metadata '" + name + "' is missing or has the wrong type");
    return m->value();
}

// An integer written as Int32 or Int64: other tools rewrite one as the
// other (pyopenvdb stores every Python int as Int32), and the file is the same.
std::int64_t required_int(const openvdb::MetaMap& meta, const std::string& path, const std::string& name) {
    if (const auto m = meta.getMetadata<openvdb::Int64Metadata>(name)) return m->value();
    if (const auto m = meta.getMetadata<openvdb::Int32Metadata>(name)) return m->value();
    fail_file(path, "metadata '" + name + "' is missing or not an integer");
}


// The volume's parameters from its jade: metadata, checked; no levels yet.
MaterialVolume material_from_metadata(const openvdb::MetaMap& meta, const std::string& path) {
    const auto fmt = meta.getMetadata<openvdb::StringMetadata>("jade:format");
    if (!fmt || fmt->value() != kFormat)
        fail_file(path, "not a jaderender material volume (no 'jade:format' metadata)");
    if (required_int(meta, path, "jade:format_version") > kFormatVersion)
        fail_file(path, "written by a newer jaderender (format version too high)");

    MaterialVolume v;
    v.resolution = int(required_int(meta, path, "jade:resolution"));
    v.photo = required_meta<std::string>(meta, path, "jade:photo");
    // Files from before the span were matched to a photo a cube side wide.
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:photo_span")) {
        v.photo_span = m->value();
        try {
            validate_photo_span(v.photo_span, "metadata 'jade:photo_span'");
        } catch (const Error& e) {
            fail_file(path, e.what());
        }
    }
    v.noise.resolution = v.resolution;
    v.noise.octaves = int(required_int(meta, path, "jade:octaves"));
    v.noise.k = required_meta<double>(meta, path, "jade:k");
    // The seed's 32 bits survive a rewrite as a (negative) Int32.
    v.noise.seed = std::uint32_t(required_int(meta, path, "jade:seed"));
    // Files from before the structure was chosen have the paper's fBm.
    if (const auto m = meta.getMetadata<openvdb::StringMetadata>("jade:structure")) {
        try {
            v.structure = parse_structure_mode(m->value());
        } catch (const Error&) {
            fail_file(path, std::string("metadata 'jade:structure' must be ") + structure_mode_names());
        }
        v.noise.exemplar = v.structure == StructureMode::Exemplar;
    }
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:exemplar_wander"))
        v.noise.exemplar_wander = m->value();
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:frequency")) v.noise.frequency = m->value();
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:stretch")) v.noise.stretch = m->value();
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:angle")) v.noise.angle = m->value();
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:bands")) v.noise.bands = m->value();
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:warp")) v.noise.warp = m->value();
    // Files from before the fold have its isotropic warp, the default.
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:fold")) v.noise.fold = m->value();
    // Files from before the veins have none.
    if (meta.getMetadata<openvdb::Int32Metadata>("jade:veins") ||
        meta.getMetadata<openvdb::Int64Metadata>("jade:veins")) {
        const std::int64_t veins = required_int(meta, path, "jade:veins");
        if (veins != 0 && veins != 1) fail_file(path, "metadata 'jade:veins' must be 0 or 1");
        v.noise.veins = veins == 1;
    }
    // Files from before the veins' own fBm have the defaults (their veins
    // were the noise's absolute value: their levels are stored, but the
    // parameters no longer rebuild them).
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:vein_frequency"))
        v.noise.vein_frequency = m->value();
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:vein_width")) v.noise.vein_width = m->value();
    // Files from before the sharpening were not sharpened.
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:sharpen")) v.noise.sharpen = m->value();
    if (const auto m = meta.getMetadata<openvdb::DoubleMetadata>("jade:sharpen_radius"))
        v.noise.sharpen_radius = m->value();
    // Files from before the layers have none.
    if (meta.getMetadata<openvdb::Int32Metadata>("jade:layers") ||
        meta.getMetadata<openvdb::Int64Metadata>("jade:layers")) {
        const std::int64_t layers = required_int(meta, path, "jade:layers");
        if (layers != 0 && layers != 1) fail_file(path, "metadata 'jade:layers' must be 0 or 1");
        v.noise.layers = layers == 1;
    }
    v.match = parse_match_mode(required_meta<std::string>(meta, path, "jade:match"));
    // Files from before the grey extinction have §5.1's.
    v.optics.extinction = Extinction::Paper;
    if (const auto m = meta.getMetadata<openvdb::StringMetadata>("jade:extinction")) {
        try {
            v.optics.extinction = parse_extinction(m->value());
        } catch (const Error&) {
            fail_file(path, "metadata 'jade:extinction' must be 'grey' or 'paper', not '" + m->value() + "'");
        }
    }
    v.optics.ds = required_meta<double>(meta, path, "jade:ds");
    v.optics.da = required_meta<double>(meta, path, "jade:da");
    const auto ks = required_meta<openvdb::Vec3d>(meta, path, "jade:ks");
    v.optics.ks = {ks[0], ks[1], ks[2]};
    v.optics.density_scale = required_meta<double>(meta, path, "jade:density_scale");
    // Files from before the contrast lever hold the paper's levels (g = 1);
    // their mean level is then taken from the levels read.
    if (const auto m = meta.getMetadata<openvdb::Vec3DMetadata>("jade:contrast"))
        v.optics.contrast = {m->value()[0], m->value()[1], m->value()[2]};
    if (const auto m = meta.getMetadata<openvdb::Vec3DMetadata>("jade:mean_level"))
        v.optics.mean_level = {m->value()[0], m->value()[1], m->value()[2]};
    else if (v.optics.contrast != std::array<double, 3>{1, 1, 1})
        fail_file(path, "metadata 'jade:contrast' needs 'jade:mean_level'");
    const auto cmin = required_meta<openvdb::Vec3d>(meta, path, "jade:cube_min");
    v.cube.min = {cmin[0], cmin[1], cmin[2]};
    v.cube.side = required_meta<double>(meta, path, "jade:cube_side");
    // Files from before the exposure was stored have none: 0, never fitted.
    if (const auto e = meta.getMetadata<openvdb::DoubleMetadata>("jade:exposure")) v.exposure = e->value();
    if (!(v.exposure >= 0.0) || !std::isfinite(v.exposure))
        fail_file(path, "metadata 'jade:exposure' must be a finite number >= 0");
    if (v.resolution < 1 || v.resolution > 4096 || !(v.cube.side > 0))
        fail_file(path, "metadata gives an impossible resolution or cube side");
    try {
        v.optics.validate();
        v.noise.validate();
    } catch (const Error& e) {
        fail_file(path, std::string("metadata: ") + e.what());
    }
    return v;
}

// Whether a stored coefficient is the one a level gives, to half-float precision.
bool same_coefficient(float want, float got) { return std::abs(want - got) <= 1e-3f * std::abs(want) + 1e-6f; }

// The level of one channel of one voxel: the level whose two coefficients are
// nearest the stored ones (levels the contrast clips give the same pair, and
// any of them will do). -1 when the grids do not follow from a level and the
// metadata (to half-float precision). A search over the table rather than the
// formula's inverse, so that it holds for either extinction; LevelMemo below
// asks it about once per distinct pair.
int level_of_channel(int c, float ss, float sa, const CoefficientTable& table) {
    int best = 0;
    float best_gap = std::numeric_limits<float>::infinity();
    for (int l = 0; l < 256; ++l) {
        const float gap = std::abs(table.sigma_s[c][l] - ss) + std::abs(table.sigma_a[c][l] - sa);
        if (gap < best_gap) best = l, best_gap = gap;
    }
    return same_coefficient(table.sigma_s[c][best], ss) && same_coefficient(table.sigma_a[c][best], sa) ? best : -1;
}

// level_of_channel remembered per channel for the (sigma_s, sigma_a) pairs
// met: a volume holds at most 256 distinct pairs per channel, so almost every
// voxel is a lookup (reading a 256³ volume: 2.2 s of inversions → a fraction).
// One per thread.
class LevelMemo {
public:
    explicit LevelMemo(const CoefficientTable& t) : table_(t) {
        for (auto& slots : slots_) slots.fill(Slot{});
    }
    int level(int c, float ss, float sa) {
        std::uint32_t a, b;
        std::memcpy(&a, &ss, 4);
        std::memcpy(&b, &sa, 4);
        const std::uint64_t key = (std::uint64_t(a) << 32) | b;
        Slot& slot = slots_[c][(key * 0x9E3779B97F4A7C15ull) >> (64 - kBits)];
        if (!slot.used || slot.key != key) slot = {key, level_of_channel(c, ss, sa, table_), true};
        return slot.level;
    }

private:
    static constexpr int kBits = 10;
    struct Slot {
        std::uint64_t key = 0;
        int level = -1;
        bool used = false;
    };
    const CoefficientTable& table_;
    std::array<std::array<Slot, 1u << kBits>, 3> slots_;
};

constexpr const char* kNotFollowing =
    "its sigma_s/sigma_a grids do not follow from its jade: metadata (damaged, cut short, or edited by another tool)";

// What a slab of the coefficient grids is read for.
enum class SlabUse {
    Recover,  // format 1: the levels from the coefficients
    Verify    // format 2: the coefficients (where active) against the levels read
};

// The sigma_s and sigma_a grids of z-slices [z0, z1), clipped to them, for
// `use`. False on a voxel whose grids do not follow from the levels and the
// metadata.
bool read_level_slab(openvdb::io::File& file, const std::string& path, int z0, int z1, MaterialVolume& v,
                     const CoefficientTable& table, SlabUse use, bool z_up) {
    const int s = v.resolution;
    const double h = v.voxel_size();
    const auto& m = v.cube.min;
    // World bounds of the slab's voxel centres, a quarter voxel wider on each
    // side: OpenVDB clips to the voxels whose centres lie inside, and with the
    // centres exactly on the bounds rounding dropped the last row at some
    // sizes (12³ could not be read back).
    const double margin = 0.25 * h;
    openvdb::BBoxd box(
        openvdb::Vec3d(m[0] + 0.5 * h - margin, m[1] + 0.5 * h - margin, m[2] + (z0 + 0.5) * h - margin),
        openvdb::Vec3d(m[0] + (s - 0.5) * h + margin, m[1] + (s - 0.5) * h + margin, m[2] + (z1 - 0.5) * h + margin));
    if (z_up)  // the same box in the turned world: (x, y, z) → (x, −z, y)
        box = openvdb::BBoxd(openvdb::Vec3d(box.min().x(), -box.max().z(), box.min().y()),
                             openvdb::Vec3d(box.max().x(), -box.min().z(), box.max().y()));
    openvdb::Vec3fGrid::Ptr gs, ga;
    try {
        gs = openvdb::gridPtrCast<openvdb::Vec3fGrid>(file.readGrid("sigma_s", box));
        ga = openvdb::gridPtrCast<openvdb::Vec3fGrid>(file.readGrid("sigma_a", box));
    } catch (const openvdb::Exception& e) {
        fail_file(path, std::string("cannot read as OpenVDB: ") + e.what());
    } catch (const std::bad_alloc&) {
        fail_vdb_too_large(path);
    }
    if (!gs || !ga) fail_file(path, "'sigma_s' and 'sigma_a' must be Vec3f grids");
    std::atomic<bool> ok{true};
    tbb::parallel_for(z0, z1, [&](int z) {
        auto acc_s = gs->getConstAccessor();
        auto acc_a = ga->getConstAccessor();
        auto memo = use == SlabUse::Recover ? std::make_unique<LevelMemo>(table) : nullptr;
        for (int y = 0; y < s; ++y)
            for (int x = 0; x < s; ++x) {
                const openvdb::Coord xyz(x, y, z);
                const openvdb::Vec3f ss = acc_s.getValue(xyz), sa = acc_a.getValue(xyz);
                Rgb8& lv = v.levels[v.index(x, y, z)];
                if (use == SlabUse::Verify) {
                    // Outside the mesh the grids are empty (a masked file).
                    if (!acc_s.isValueOn(xyz) && !acc_a.isValueOn(xyz)) continue;
                    for (int c = 0; c < 3; ++c)
                        if (!same_coefficient(table.sigma_s[c][lv[c]], ss[c]) ||
                            !same_coefficient(table.sigma_a[c][lv[c]], sa[c]))
                            ok = false;
                    continue;
                }
                for (int c = 0; c < 3; ++c) {
                    const int l = memo->level(c, ss[c], sa[c]);
                    if (l < 0) ok = false;
                    lv[c] = std::uint8_t(std::max(l, 0));
                }
            }
    });
    return ok;
}

}  // namespace

namespace {

// Memory a .vdb's header, metadata and grid descriptors may take to read:
// names, types and metadata values of a few kilobytes each, far below this.
constexpr std::uint64_t kHeaderBudgetBytes = 512ull << 20;
// CPU time the header may take, and the grids beyond it per voxel of each of
// four grids: the demo's 256³ volume is allowed 94 s and reads in 1.0 s.
constexpr int kHeaderCpuSeconds = 60;
constexpr double kGridCpuSecondsPerVoxel = 1.0 / 2e6;

// The checking program: beside this executable (jaderender and its helper
// are built and copied together), else where the build tree made it.
std::string vdb_check_program(const std::string& path) {
    const std::string beside = own_executable_dir();
    if (!beside.empty() && ::access((beside + "/" + kVdbCheckProgram).c_str(), X_OK) == 0)
        return beside + "/" + kVdbCheckProgram;
    if (::access(JADE_VDB_CHECK_PATH, X_OK) == 0) return JADE_VDB_CHECK_PATH;
    fail_file(path, std::string("cannot be checked before reading it: the program ") + kVdbCheckProgram +
                        " is neither beside this one nor at " JADE_VDB_CHECK_PATH);
}

// Reads `part` of the file in a process of its own (the program
// jaderender-vdb-check: run_vdb_check, vdb_check.h) and refuses the file, in one
// line, when that process reports OpenVDB's error, runs out of its memory or
// CPU budget, or is killed by a crash.
void check_in_own_process(const std::string& path, VdbCheck part, std::uint64_t budget, int cpu_seconds) {
    const std::string program = vdb_check_program(path);
    const ProcessResult r = run_program(
        program, {to_string(part), path, std::to_string(budget), std::to_string(cpu_seconds)});
    const std::string what = to_string(part);
    if (!r.started) fail_file(path, "cannot be checked before reading it: " + program + " did not start");
    if (r.exit_code == 0) return;
    if (r.exit_code == 1) fail_file(path, "cannot read as OpenVDB: " + r.output);
    if (r.exit_code == 2) fail_file(path, "damaged: its " + what + " asks for more memory than it can need");
    if (r.signal == SIGXCPU)
        fail_file(path, "damaged: OpenVDB did not finish reading its " + what + " in " +
                            std::to_string(cpu_seconds) + " s of CPU time");
    if (r.signal != 0) fail_file(path, "damaged: OpenVDB fails reading its " + what);
    fail_file(path, "cannot be checked before reading it: " + program + " exited with code " +
                        std::to_string(r.exit_code));
}

// The existence check, header, metadata and every grid's descriptor and
// metadata, read in a process of its own: a damaged .vdb can make OpenVDB
// allocate whatever a corrupt length field in its header says (a "grid type"
// of 1.45 GB, 8.6 GB resident) before it fails.
void check_vdb_header(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail_file(path, "no such file");
    check_in_own_process(path, VdbCheck::Header, kHeaderBudgetBytes, kHeaderCpuSeconds);
}

// Every grid of a jaderender volume of s³ voxels read whole in a process of
// its own, allowed the memory four float grids of the cube take (and the
// header's budget) and no more: a file that crashes OpenVDB or asks for more
// is refused before this process reads it.
void check_vdb_grids(const std::string& path, int resolution) {
    const std::uint64_t s = std::uint64_t(resolution);
    const double voxels = 4.0 * double(s * s * s);
    check_in_own_process(path, VdbCheck::Grids, kHeaderBudgetBytes + 48 * s * s * s,
                         kHeaderCpuSeconds + int(std::ceil(voxels * kGridCpuSecondsPerVoxel)));
}

}  // namespace

namespace {

// Grid `name` read whole as a GridT; a grid of another type is refused with
// `type_name` in the message.
template <typename GridT>
typename GridT::Ptr read_whole_grid(openvdb::io::File& file, const std::string& path, const std::string& name,
                                    const char* type_name) {
    typename GridT::Ptr grid;
    try {
        grid = openvdb::gridPtrCast<GridT>(file.readGrid(name));
    } catch (const openvdb::Exception& e) {
        fail_file(path, std::string("cannot read as OpenVDB: ") + e.what());
    } catch (const std::bad_alloc&) {
        fail_vdb_too_large(path);
    }
    if (!grid) fail_file(path, "its '" + name + "' grid is not " + type_name + " grid");
    return grid;
}

// Format 2: the levels grid, read whole and unpacked by index (whatever
// way its transform turns the world).
void read_levels_grid(openvdb::io::File& file, const std::string& path, MaterialVolume& v) {
    const auto grid = read_whole_grid<openvdb::Int32Grid>(file, path, kLevelsGrid, "an Int32");
    const int s = v.resolution;
    std::atomic<bool> ok{true};
    tbb::parallel_for(0, s, [&](int z) {
        auto acc = grid->getConstAccessor();
        for (int y = 0; y < s; ++y)
            for (int x = 0; x < s; ++x) {
                const std::int32_t packed = acc.getValue(openvdb::Coord(x, y, z));
                if (packed < 0 || packed >= (1 << 24)) ok = false;
                v.levels[v.index(x, y, z)] = {std::uint8_t(packed), std::uint8_t(packed >> 8),
                                              std::uint8_t(packed >> 16)};
            }
    });
    if (!ok) fail_file(path, "its 'levels' grid holds values that are not 8-bit RGB levels (damaged)");
}

// Format 2: the coefficient grids (where active: inside the mesh when
// masked) checked against the levels read, so that a file whose grids
// another tool edited is refused rather than rendered as if unedited. Read
// whole, as check_vdb_grids had jaderender-vdb-check read them.
void verify_coefficient_grids(openvdb::io::File& file, const std::string& path, const MaterialVolume& v) {
    const CoefficientTable table(v.optics, v.cube.side);
    const int s = v.resolution;
    for (const char* name : {"sigma_s", "sigma_a"}) {
        if (!file.hasGrid(name)) continue;
        const auto grid = read_whole_grid<openvdb::Vec3fGrid>(file, path, name, "a Vec3f");
        const auto& column = name[6] == 's' ? table.sigma_s : table.sigma_a;
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const openvdb::CoordBBox box = it.getBoundingBox();
            for (auto xyz = box.begin(); xyz; ++xyz) {
                const openvdb::Coord c = *xyz;
                const bool inside = c.x() >= 0 && c.y() >= 0 && c.z() >= 0 && c.x() < s && c.y() < s && c.z() < s;
                const Rgb8 lv = inside ? v.levels[v.index(c.x(), c.y(), c.z())] : Rgb8{0, 0, 0};
                const openvdb::Vec3f value = *it;
                for (int ch = 0; ch < 3 && inside; ++ch)
                    if (!same_coefficient(column[ch][lv[ch]], value[ch])) fail_file(path, kNotFollowing);
                if (!inside) fail_file(path, kNotFollowing);
            }
        }
    }
}

// The coefficient grids read by slabs: format 1 recovers the levels from them,
// format 2 checks them against its levels (a file whose grids another tool
// edited is refused rather than rendered as if unedited).
void read_coefficient_slabs(openvdb::io::File& file, const std::string& path, MaterialVolume& v, SlabUse use,
                            bool z_up) {
    const int s = v.resolution;
    const CoefficientTable table(v.optics, v.cube.side);
    // A slab of z-slices at a time (OpenVDB skips the leaves outside a
    // clipping box): reading costs a slab's worth of float grids beside the
    // 3-byte levels instead of two whole Vec3f grids.
    constexpr int kSlab = 32;
    bool consistent = true;
    for (int z0 = 0; z0 < s; z0 += kSlab)
        consistent = read_level_slab(file, path, z0, std::min(s, z0 + kSlab), v, table, use, z_up) && consistent;
    if (!consistent) fail_file(path, kNotFollowing);
}

}  // namespace

MaterialVolume read_material_vdb(const std::string& path) {
    openvdb::initialize();
    check_vdb_header(path);
    openvdb::MetaMap::Ptr meta;
    std::unique_ptr<openvdb::io::File> file;
    try {
        file = std::make_unique<openvdb::io::File>(path);
        file->open(false);  // no memory mapping: mapped pages would count as our memory
        meta = file->getMetadata();
        if (!file->hasGrid(kLevelsGrid) && (!file->hasGrid("sigma_s") || !file->hasGrid("sigma_a")))
            fail_file(path, "no 'levels' grid, nor 'sigma_s' and 'sigma_a' grids");
    } catch (const openvdb::Exception& e) {
        fail_file(path, std::string("cannot read as OpenVDB: ") + e.what());
    } catch (const std::bad_alloc&) {
        fail_vdb_too_large(path);
    }
    MaterialVolume v = material_from_metadata(*meta, path);
    const int s = v.resolution;
    check_vdb_grids(path, s);
    v.levels.assign(std::size_t(s) * s * s, Rgb8{0, 0, 0});
    const auto up = meta->getMetadata<openvdb::StringMetadata>("jade:up_axis");
    const bool z_up = up && up->value() == "z";
    if (file->hasGrid(kLevelsGrid)) {
        read_levels_grid(*file, path, v);
        verify_coefficient_grids(*file, path, v);
    } else {
        read_coefficient_slabs(*file, path, v, SlabUse::Recover, z_up);
    }
    file->close();
    // Files written before the digest existed have none to compare.
    if (const auto digest = meta->getMetadata<openvdb::StringMetadata>("jade:levels_digest"))
        if (digest->value() != levels_digest(v))
            fail_file(path, "its grids do not match the digest written with them: the file is damaged or "
                            "cut short");
    if (!meta->getMetadata<openvdb::Vec3DMetadata>("jade:mean_level")) v.optics.mean_level = mean_levels(v.levels);
    return v;
}

bool is_material_vdb(const std::string& path) {
    openvdb::initialize();
    check_vdb_header(path);
    try {
        openvdb::io::File file(path);
        file.open(true);
        const auto meta = file.getMetadata();
        file.close();
        return bool(meta->getMetadata<openvdb::StringMetadata>("jade:format"));
    } catch (const openvdb::Exception& e) {
        fail_file(path, std::string("cannot read as OpenVDB: ") + e.what());
    } catch (const std::bad_alloc&) {
        fail_vdb_too_large(path);
    }
    return false;
}

namespace {

// A float or Vec3f grid, made dense as RGB over `box` (index space).
std::vector<Spectrum> dense_rgb(const openvdb::GridBase::Ptr& base, const openvdb::CoordBBox& box,
                                const std::string& path) {
    const openvdb::Coord dim = box.dim();
    std::vector<Spectrum> out(std::size_t(dim.x()) * dim.y() * dim.z(), Spectrum(0.f));
    auto fill = [&](auto grid, auto to_rgb) {
        tbb::parallel_for(0, dim.z(), [&](int k) {
            auto acc = grid->getConstAccessor();
            for (int j = 0; j < dim.y(); ++j)
                for (int i = 0; i < dim.x(); ++i)
                    out[(std::size_t(k) * dim.y() + j) * dim.x() + i] =
                        to_rgb(acc.getValue(box.min() + openvdb::Coord(i, j, k)));
        });
    };
    if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(base))
        fill(f, [](float v) { return Spectrum(v); });
    else if (auto v = openvdb::gridPtrCast<openvdb::Vec3fGrid>(base))
        fill(v, [](const openvdb::Vec3f& c) { return Spectrum(c[0], c[1], c[2]); });
    else
        fail_file(path, "grid '" + base->getName() + "' must be a float or Vec3f grid, not " +
                            base->valueType());
    return out;
}

}  // namespace

CoefficientGrids read_medium_vdb(const std::string& path, const DensityConversion& conv) {
    openvdb::initialize();
    check_vdb_header(path);
    openvdb::GridPtrVec grids;
    try {
        openvdb::io::File file(path);
        file.open(false);
        const bool coefficients = file.hasGrid("sigma_s") && file.hasGrid("sigma_a");
        const std::vector<std::string> names =
            coefficients ? std::vector<std::string>{"sigma_s", "sigma_a"}
            : file.hasGrid("color") ? std::vector<std::string>{"density", "color"}
            : file.hasGrid("Cd")    ? std::vector<std::string>{"density", "Cd"}  // Houdini's name
                                    : std::vector<std::string>{"density"};
        if (!file.hasGrid(names[0]))
            fail_file(path, "has neither 'sigma_s' + 'sigma_a' grids nor a 'density' grid");
        for (const auto& n : names) grids.push_back(file.readGrid(n));
        file.close();
    } catch (const openvdb::Exception& e) {
        fail_file(path, std::string("cannot read as OpenVDB: ") + e.what());
    } catch (const std::bad_alloc&) {
        fail_vdb_too_large(path);
    }

    // One axis-aligned placement for all grids.
    const openvdb::math::Transform& xf = grids[0]->transform();
    for (const auto& g : grids)
        if (g->transform() != xf) fail_file(path, "its grids have different transforms");
    const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0.0));
    openvdb::Vec3d spacing;
    for (int a = 0; a < 3; ++a) {
        openvdb::Vec3d e(0.0);
        e[a] = 1.0;
        const openvdb::Vec3d step = xf.indexToWorld(e) - o;
        for (int b = 0; b < 3; ++b)
            if (b != a && std::abs(step[b]) > 1e-9 * step.length())
                fail_file(path, "its grid transform is rotated or sheared; only axis-aligned "
                                "grids are supported");
        if (!(step[a] > 0.0) || !xf.isLinear())
            fail_file(path, "its grid transform is not a positive scale per axis");
        spacing[a] = step[a];
    }
    openvdb::CoordBBox box;
    for (const auto& g : grids) box.expand(g->evalActiveVoxelBoundingBox());
    if (box.empty()) fail_file(path, "its grids have no active voxel");
    const openvdb::Coord dim = box.dim();
    if (double(dim.x()) * dim.y() * dim.z() > 1024.0 * 1024 * 1024)
        fail_file(path, "its grids span more than 1024^3 voxels");

    CoefficientGrids out;
    out.placement.size = {dim.x(), dim.y(), dim.z()};
    const openvdb::Vec3d origin = xf.indexToWorld(box.min().asVec3d());
    out.placement.origin = glm::vec3(float(origin[0]), float(origin[1]), float(origin[2]));
    out.placement.spacing = glm::vec3(float(spacing[0]), float(spacing[1]), float(spacing[2]));
    if (grids[0]->getName() == "sigma_s") {
        out.sigma_s = dense_rgb(grids[0], box, path);
        grids[0].reset();
        out.sigma_a = dense_rgb(grids[1], box, path);
    } else {
        std::vector<Spectrum> density = dense_rgb(grids[0], box, path);
        grids[0].reset();
        std::vector<Spectrum> albedo;
        if (grids.size() > 1) albedo = dense_rgb(grids[1], box, path);
        out.sigma_s.resize(density.size());
        out.sigma_a.resize(density.size());
        for (std::size_t i = 0; i < density.size(); ++i) {
            const Spectrum a = glm::clamp(albedo.empty() ? conv.albedo : albedo[i], 0.f, 1.f);
            const Spectrum t = conv.scale * density[i];
            out.sigma_s[i] = a * t;
            out.sigma_a[i] = (1.f - a) * t;
        }
    }
    return out;
}

}  // namespace jade

namespace jade {
const char* openvdb_version() { return openvdb::getLibraryVersionString(); }
}  // namespace jade
