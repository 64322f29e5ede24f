// jaderender: the command-line front end. It parses flags and calls the
// library; all the work lives in libjade.

#include "jade/io/atomic_file.h"
#include "jade/app/batch.h"
#include "jade/app/bench.h"
#include "jade/core/error.h"
#include "jade/core/parse.h"
#include "jade/io/image_io.h"
#include "jade/volume/material_volume.h"
#include "jade/volume/photo.h"
#include "jade/volume/sharpen.h"
#include "jade/app/pipeline.h"
#include "jade/core/progress.h"
#include "jade/app/job.h"
#include "jade/app/render_job.h"
#include "jade/app/report.h"
#include "jade/core/timing.h"
#include "jade/io/vdb_io.h"

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace {

// "x,y,z" (or one number for all three) as a CLI11 validator + converter.
struct Vec3Flag {
    std::string text;
    bool given() const { return !text.empty(); }
    glm::vec3 value(const char* flag) const {
        jade::Spectrum v;
        if (!jade::parse_vec3(text, v))
            throw jade::Error(std::string(flag) + " expects x,y,z (or one number), not '" + text + "'");
        return v;
    }
};

struct VolumeOptions {
    std::string photo, mask, out, preview, color_name = "color";
    double photo_span = 1.0;  // Photo::span
    bool z_up = false;
    jade::NoiseParams noise = jade::default_photo_noise();
    std::string sharpen = "auto";  // --sharpen: sharpen_amount
    std::string structure = "photo";
    std::string match = "joint";
    std::string extinction = jade::to_string(jade::OpticalParams{}.extinction);
    jade::OpticalParams optics;
    Vec3Flag contrast;  // `volume --contrast`
};

// Puts the options added to `cmd` from index `first` on into help section
// `group`, so that --help reads as sections rather than one long list.
void group_from(CLI::App& cmd, std::size_t first, const std::string& group) {
    const std::vector<CLI::Option*> options = cmd.get_options();
    for (std::size_t i = first; i < options.size(); ++i) options[i]->group(group);
}

// A number as --help prints it: "0.5", not "0.500000".
std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// The amount --sharpen gives: a number, or for 'auto' kDefaultSharpen (the
// `volume` command's; the fit chooses its own: PipelineOptions::sharpen_from_fit).
double sharpen_amount(const std::string& text) {
    if (text == "auto") return jade::kDefaultSharpen;
    std::size_t used = 0;
    double amount = 0.0;
    try {
        amount = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size())
        throw jade::Error("--sharpen must be 'auto' or an amount (0 = none), not '" + text + "'");
    return amount;
}

void add_volume_flags(CLI::App& cmd, VolumeOptions& o, bool photo_required = true) {
    const std::size_t first = cmd.get_options().size();
    auto* photo = cmd.add_option("--photo", o.photo, "Photograph of the material (PNG, JPEG, TIFF, EXR; "
                                                     "alpha >= 0.5 marks the object)");
    if (photo_required) photo->required();
    cmd.add_option("--mask", o.mask, "Mask image, same size as the photo; white (>= 0.5) = "
                                     "object. Replaces the photo's alpha");
    cmd.add_option("--photo-span", o.photo_span,
                   "How many of the object's sizes (its bounding cube's side) the photo's width spans: 1 as "
                   "wide as the object, 4 a slab four times as wide, the object showing a quarter of it, its "
                   "structure four times coarser (1/8 to 8)")
        ->capture_default_str();
    cmd.add_option("--resolution", o.noise.resolution, "Voxels along each side of the cube (s)")
        ->capture_default_str();
    cmd.add_option("--octaves", o.noise.octaves, "fBm octaves n (0 = floor(log2(s)), the paper's)")
        ->capture_default_str();
    cmd.add_option("--structure", o.structure,
                   "Structure: 'photo' (a noise whose frequency, k, stretch, angle, bands and folds are "
                   "estimated from the photo's spectrum), 'exemplar' (the photo itself swept through the cube's "
                   "depth: every slice facing the camera is the photo, moved as --exemplar-wander says; across, "
                   "stripes) or 'fbm' "
                   "(the paper's, or as given by --frequency, --k, --stretch, --angle)")
        ->capture_default_str();
    cmd.add_option("--k", o.noise.k,
                   "fBm amplitude ratio k, 0 < k < 1; with --layers, the layers' profile's (--structure fbm)")
        ->capture_default_str();
    cmd.add_option("--frequency", o.noise.frequency,
                   "fBm base frequency, cycles per cube side (--structure fbm)")
        ->capture_default_str();
    cmd.add_option("--stretch", o.noise.stretch,
                   "Elongation of the noise along --angle and depth, >= 1 (--structure fbm)")
        ->capture_default_str();
    cmd.add_option("--angle", o.noise.angle,
                   "Direction of the stretch, degrees counterclockwise from +x as seen from +z "
                   "(--structure fbm)")
        ->capture_default_str();
    cmd.add_option("--bands", o.noise.bands,
                   "Layers per cube side across --angle, warped by the fBm (Perlin's marble); 0 = plain "
                   "fBm (--structure fbm)")
        ->capture_default_str();
    cmd.add_option("--warp", o.noise.warp, "How far the fBm displaces the layers, in cube sides (--structure fbm)")
        ->capture_default_str();
    cmd.add_option("--fold", o.noise.fold,
                   "How fast the warp varies across the layers against along them, 0 to 1: 1 isotropic (folds "
                   "may overturn into rings), 0 every layer folds alike (--structure fbm, with --bands)")
        ->capture_default_str();
    cmd.add_option("--veins", o.noise.veins,
                   "Thin veins through the structure, where a second fBm is near zero: they get the photo's "
                   "darkest colours, in curves that branch and join as marble's do (with --structure photo "
                   "the estimate then searches their frequency and width too; it does not choose veins by itself)")
        ->capture_default_str();
    cmd.add_option("--vein-frequency", o.noise.vein_frequency,
                   "With --veins: cycles per cube side of the veins' first octave (--structure fbm)")
        ->capture_default_str();
    cmd.add_option("--vein-width", o.noise.vein_width,
                   "With --veins: the veins' half-width, a share of their fBm's range about zero; 0.005 is one "
                   "to two voxels (--structure fbm)")
        ->capture_default_str();
    cmd.add_option("--layers", o.noise.layers,
                   "With --bands: a 1-D fBm across the layers (its octaves' amplitude ratio --k) instead of the "
                   "sine, so the layers have many thicknesses, folded by the paper's smooth fBm")
        ->capture_default_str();
    cmd.add_option("--sharpen", o.sharpen,
                   "Unsharp mask on the matched levels, v + amount (v - Gaussian blur of v): fine structure "
                   "(veins, layers) stronger, so that more of it survives the light's diffusion. 'auto': the "
                   "fit chooses: it fits the unsharpened stone, and where it raised the density scale, fits it "
                   "again sharpened by " + number(jade::kSharperStone) + " (" + number(jade::kDefaultSharpen) +
                       " where the density reached its ceiling), kept where that fit converges (`volume`, which "
                       "fits nothing: " + number(jade::kDefaultSharpen) + "); an amount: that one alone; 0 = none "
                       "(the paper's)")
        ->capture_default_str();
    cmd.add_option("--sharpen-radius", o.noise.sharpen_radius,
                   "With --sharpen: the blur's standard deviation, voxels")
        ->capture_default_str();
    cmd.add_option("--exemplar-wander", o.noise.exemplar_wander,
                   "With --structure exemplar: how far the photo's offset wanders through the cube's depth, "
                   "cube sides (0 = the photo drawn straight through)")
        ->capture_default_str();
    cmd.add_option("--seed", o.noise.seed, "Noise seed")->capture_default_str();
    cmd.add_option("--match", o.match, "Colour matching: 'joint' (real photo colours) or "
                                       "'per-channel' (the paper's)")
        ->capture_default_str();
    cmd.add_option("--extinction", o.extinction,
                   "'grey': every voxel and channel takes the extinction d_s and keeps the paper's albedo "
                   "sigma_s / (sigma_s + sigma_a), so the stone's colour is its absorption; 'paper': "
                   "sigma_s + sigma_a as the paper's formulas give them (the same at k_s = 0, d_a = 1)")
        ->capture_default_str();
    cmd.add_option("--ds", o.optics.ds, "Scattering scale d_s")->capture_default_str();
    cmd.add_option("--da", o.optics.da, "Absorption scale d_a")->capture_default_str();
    cmd.add_option("--density-scale", o.optics.density_scale,
                   "Optical thickness across the object for a coefficient of 1 (--fit contrast may raise it, "
                   "see --fit-density)")
        ->capture_default_str();
    group_from(cmd, first, "Photo and material volume");
}

int run_volume(VolumeOptions& o) {
    const jade::Stopwatch total;
    const jade::MatchMode match = jade::parse_match_mode(o.match);
    o.optics.extinction = jade::parse_extinction(o.extinction);
    if (o.contrast.given()) {
        const glm::vec3 g = o.contrast.value("--contrast");
        o.optics.contrast = {g.x, g.y, g.z};
    }
    o.noise.sharpen = sharpen_amount(o.sharpen);
    o.noise.validate();
    o.optics.validate();
    // Refuse a missing output folder now, not after seconds of work.
    jade::require_output_folder(o.out);
    if (!o.preview.empty()) jade::require_output_folder(o.preview);
    jade::require_memory_for_volume(o.noise.resolution);

    const jade::Stopwatch t_photo;
    const jade::Photo photo = jade::load_photo(o.photo, o.mask, o.photo_span);
    const double photo_s = t_photo.seconds();

    const jade::Stopwatch t_volume;
    const jade::StructureMode structure = jade::parse_structure_mode(o.structure);
    jade::StructureEstimate estimate;
    const jade::NoiseParams noise = jade::choose_noise(photo, o.noise, structure, &estimate);
    jade::MaterialVolume volume;
    {
        jade::Progress progress("noise + colour matching", std::size_t(o.noise.resolution));
        volume = jade::build_material_volume(photo, noise, match, o.optics, &progress);
    }
    const std::string clipped = jade::sharpening_warning(noise.sharpen, volume.sharpen_clipped);
    if (!clipped.empty()) std::fprintf(stderr, "jaderender: warning: volume: %s\n", clipped.c_str());
    volume.structure = structure;
    const double volume_s = t_volume.seconds();

    const jade::Stopwatch t_write;
    jade::write_material_vdb(o.out, volume, jade::VdbLayout{nullptr, o.z_up, o.color_name});
    const double write_s = t_write.seconds();

    if (structure == jade::StructureMode::Photo)
        std::printf("structure from the photo%s in %.2f s: slice-to-photo structure distance %.3f (the paper's "
                    "fBm: %.3f); orientation strength %.2f, coherence %.2f, "
                    "orientation defects %.3f (photo: %.2f, %.2f, %.3f)\n",
                    jade::photo_span_note(photo.span).c_str(),
                    estimate.seconds, estimate.chosen.distance, estimate.paper.distance, estimate.chosen.strength,
                    estimate.chosen.coherence, estimate.chosen.defects, estimate.photo.strength,
                    estimate.photo.coherence, estimate.photo.defects);
    {
        const jade::StructureFit built = jade::measure_slice_structure(volume.levels, volume.resolution, photo);
        std::printf("the volume's slices: structure distance %.3f, orientation strength %.2f, coherence %.2f, "
                    "orientation defects %.3f\n",
                    built.distance, built.strength, built.coherence, built.defects);
        const jade::StructureFit across = jade::measure_slice_structure_across(volume.levels, volume.resolution, photo);
        std::printf("the volume's slices across (normal to x and y): structure distance %.3f, orientation strength "
                    "%.2f, coherence %.2f, orientation defects %.3f\n",
                    across.distance, across.strength, across.coherence, across.defects);
    }
    if (!o.preview.empty()) {
        const jade::RgbImage8 slice = jade::slice_image(volume, volume.resolution / 2);
        jade::write_image_u8(o.preview, slice.width, slice.height, 3, slice.pixels);
    }

    // The swept photo has no noise parameters to show.
    char parameters[200] = "";
    if (!noise.exemplar)
        std::snprintf(parameters, sizeof parameters, " frequency %.2f, k %.2f, stretch %.2f, angle %.1f, bands %.1f, "
                      "warp %.2f", noise.frequency, noise.k, noise.stretch, noise.angle, noise.bands, noise.warp);
    std::string family = noise.family_suffix();
    if (noise.exemplar && family.size() > 2) family = family.substr(1);  // its leading comma
    std::printf("volume: %d^3 = %.1f M voxels (%s match, %zu foreground pixels); structure %s:%s%s; photo %.2f s, "
                "structure+noise+matching %.2f s, vdb write %.2f s; %s %s; total %.2f s, peak memory %s\n",
                volume.resolution, double(volume.levels.size()) / 1e6, jade::to_string(match),
                photo.foreground_count(), jade::to_string(structure), parameters, family.c_str(),
                photo_s, volume_s, write_s, o.out.c_str(),
                jade::format_megabytes(double(jade::file_size(o.out))).c_str(), total.seconds(),
                jade::format_megabytes(double(jade::peak_rss_bytes())).c_str());
    return 0;
}


struct RenderFlags {
    std::string job_file;
    jade::RenderJob job;
    std::string boundary = "split";
    std::string light_nee = "auto";
    std::string light_chain = "auto";
    std::string samples, pixels, piece_of;  // a piece of the render
    Vec3Flag sigma_s, sigma_a, ks, contrast, vdb_albedo, origin, target, up, light_dir;
    std::string sphere;
    std::string job_mesh;  // the --job's own mesh, to tell a --mesh given beside it
};

// `render --job FILE`: the job is read before the flags are parsed, so that
// the flags given land on top of it (CLI11 writes only the options given).
// Returns false (after printing the error) when the file cannot be used.
bool preload_job(int argc, char** argv, RenderFlags& f) {
    bool in_render = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "render") in_render = true;
        if (!in_render) continue;
        std::string path;
        if (arg == "--job" && i + 1 < argc) path = argv[i + 1];
        if (arg.rfind("--job=", 0) == 0) path = arg.substr(6);
        if (path.empty()) continue;
        try {
            f.job = jade::load_job(path);
        } catch (const jade::Error& e) {
            std::fprintf(stderr, "jaderender: error: %s\n", e.what());
            return false;
        }
        f.job_mesh = f.job.mesh;
        f.boundary = jade::to_string(f.job.interface.mode);
        f.light_nee = jade::to_string(f.job.settings.integrator.light_through_boundary);
        f.light_chain = jade::to_string(f.job.settings.integrator.light_chain);
    }
    return true;
}

// The render command's own flags: its medium and mesh.
void add_medium_flags(CLI::App& cmd, RenderFlags& f) {
    jade::RenderJob& j = f.job;
    const std::size_t first = cmd.get_options().size();
    cmd.add_option("--job", f.job_file,
                   "Render the job in this file (a job document, or a report.json whose final render "
                   "it replays); flags given beside it override its keys");
    cmd.add_option("--mesh", j.mesh, "The object's surface (.obj, .gltf, .glb); closed, outward-facing");
    cmd.add_option("--sphere", f.sphere,
                   "An analytic sphere instead of --mesh: centre and radius x,y,z,r (exact normals, no "
                   "triangles; reference scenes A and B)");
    cmd.add_option("--volume", j.volume,
                   "Medium: a jaderender .vdb (mapped onto the mesh's bounding cube) or a foreign "
                   ".vdb with world-space grids sigma_s + sigma_a, or density [+ color]");
    cmd.add_option("--sigma-s", f.sigma_s.text,
                   "Homogeneous medium instead of --volume: scattering per world unit, r,g,b");
    cmd.add_option("--sigma-a", f.sigma_a.text, "Homogeneous medium: absorption per world unit, r,g,b");
    cmd.add_option("--ks", f.ks.text, "Override the jaderender volume's fitted k_s, r,g,b");
    cmd.add_option("--contrast", f.contrast.text,
                   "Override the jaderender volume's fitted contrast, r,g,b (0..16; 1 = the paper's levels)");
    cmd.add_option("--vdb-density-scale", j.density.scale,
                   "Foreign .vdb density grid: sigma_t = scale * density")
        ->capture_default_str();
    cmd.add_option("--vdb-albedo", f.vdb_albedo.text,
                   "Foreign .vdb density grid without a color grid: albedo r,g,b (default 0.9)");
    cmd.add_flag("--flat", j.flat_normals, "Shade the boundary with face normals");
    cmd.add_flag("--allow-open", j.allow_open, "Render a mesh with many open edges anyway");
    group_from(cmd, first, "Object and medium");
    const std::size_t outputs = cmd.get_options().size();
    cmd.add_option("--reference", j.reference, "Reference image: RMSE after every pass");
    cmd.add_option("--out", j.out, "Output .exr (linear RGBA float)");
    cmd.add_option("--exposure", j.exposure,
                   "The PNG's exposure before sRGB (0 = the fitted exposure a jaderender .vdb stores, "
                   "else 1)")
        ->capture_default_str();
    cmd.add_option("--png", j.png, "sRGB PNG ('auto': beside --out; '' = none)")->capture_default_str();
    cmd.add_option("--convergence", j.convergence,
                   "Error against time, CSV, and its log-log picture as the same name .png ('auto': "
                   "<name>.convergence.csv beside --out; '' = none)")
        ->capture_default_str();
    group_from(cmd, outputs, "Output");
    const std::size_t pieces = cmd.get_options().size();
    cmd.add_option("--samples", f.samples,
                   "Render only samples A:B (A to B-1) of every pixel, as a piece for `jaderender merge`: "
                   "written beside --out as <name>.part-sA-B.exr");
    cmd.add_option("--pixels", f.pixels,
                   "Render only pixels x0:x1,y0:y1 (a tile), as a piece for `jaderender merge` (with "
                   "--samples, or all samples 0:--spp)");
    cmd.add_option("--piece", f.piece_of,
                   "Render only piece I of N (I from 0) of the samples, cut into N nearly equal ranges: "
                   "--samples for a scheduler's task I of N");
    group_from(cmd, pieces, "Split rendering (a cluster's or render farm's tasks)");
}

// The boundary and phase function flags of a render.
void add_boundary_flags(CLI::App& cmd, RenderFlags& f) {
    jade::RenderJob& j = f.job;
    const std::size_t first = cmd.get_options().size();
    cmd.add_option("--boundary", f.boundary,
                   "Interface: 'split' (paper: reflect with weight --specular), 'fresnel' (exact), "
                   "'none' (index-matched)")
        ->capture_default_str();
    cmd.add_option("--ior", j.interface.ior, "Interior index of refraction")->capture_default_str();
    cmd.add_option("--specular", j.interface.specular, "Reflection weight of the split boundary")
        ->capture_default_str();
    cmd.add_option("--g", j.g, "Henyey-Greenstein asymmetry (0 = isotropic)")->capture_default_str();
    group_from(cmd, first, "Boundary and phase function");
}

// The camera flags of a render.
void add_camera_flags(CLI::App& cmd, RenderFlags& f) {
    jade::RenderJob& j = f.job;
    const std::size_t first = cmd.get_options().size();
    cmd.add_option("--camera-origin", f.origin.text,
                   "Camera position x,y,z (default: framed from the mesh's upper front)");
    cmd.add_option("--camera-target", f.target.text, "Point looked at (default: the mesh's centre)");
    cmd.add_option("--camera-up", f.up.text, "Up vector (default 0,1,0)");
    cmd.add_option("--camera-file", j.camera_file,
                   "Use the first perspective camera of this .gltf/.glb (e.g. the mesh file)");
    cmd.add_option("--fov", j.fov_degrees, "HORIZONTAL field of view, degrees")->capture_default_str();
    cmd.add_option("--width", j.width, "Image width, pixels")->capture_default_str();
    cmd.add_option("--height", j.height, "Image height, pixels")->capture_default_str();
    group_from(cmd, first, "Camera");
}

// The lights of a render.
void add_light_flags(CLI::App& cmd, RenderFlags& f) {
    jade::RenderJob& j = f.job;
    const std::size_t first = cmd.get_options().size();
    const glm::vec3 toward = jade::RenderJob{}.light_direction;
    char toward_text[64];
    std::snprintf(toward_text, sizeof toward_text, "%g,%g,%g", toward.x, toward.y, toward.z);
    cmd.add_option("--light-dir", f.light_dir.text,
                   std::string("Direction toward the directional light (default ") + toward_text +
                       ": just above and right of the default camera's view)");
    cmd.add_option("--light-irradiance", j.light_irradiance,
                   "Its irradiance on a surface facing it (0 = off)")
        ->capture_default_str();
    cmd.add_option("--light-file", j.light_file,
                   "Use the first directional light (KHR_lights_punctual) of this .gltf/.glb (e.g. the mesh "
                   "file) for the light's direction and irradiance (its intensity in lux)");
    cmd.add_option("--light-radius", j.light_radius_degrees,
                   "Its angular radius, degrees (0 = a delta light: inside a dielectric object it "
                   "is found only along the chains of --light-chain, see also --light-nee)")
        ->capture_default_str();
    cmd.add_option("--env", j.environment,
                   "Environment: constant radiance (v or r,g,b) or a lat-long .exr/.hdr image "
                   "(importance-sampled; negative texels read as 0 with a warning)")
        ->capture_default_str();
    cmd.add_option("--env-scale", j.environment_scale, "Multiplies the environment")
        ->capture_default_str();
    cmd.add_option("--background", j.background,
                   "Image seen behind the object by camera rays that miss (default: the environment)");
    cmd.add_flag("--transparent", j.transparent,
                 "Camera rays that miss see nothing; alpha = object coverage");
    group_from(cmd, first, "Lights");
}

// How a render samples and when it stops.
void add_rendering_flags(CLI::App& cmd, RenderFlags& f, const std::string& seed_flag) {
    jade::RenderJob& j = f.job;
    const std::size_t first = cmd.get_options().size();
    cmd.add_option("--spp", j.settings.spp, "Samples per pixel (stop)")->capture_default_str();
    cmd.add_option("--time", j.settings.time_limit, "Time budget in seconds (stop; 0 = none)")
        ->capture_default_str();
    cmd.add_option("--target-error", j.settings.target_error,
                   "Estimated relative error to stop at (0 = none)")
        ->capture_default_str();
    cmd.add_option(seed_flag, j.settings.seed, "Random seed of the rendering")->capture_default_str();
    cmd.add_option("--max-depth", j.settings.integrator.max_depth,
                   "Most interactions per path; paths cut here are counted as bias")
        ->capture_default_str();
    cmd.add_option("--light-nee", f.light_nee,
                   "Next-event estimation of the light through a refracting boundary: 'manifold' "
                   "(Newton's method finds the refraction toward a point of the light), 'cone' (a "
                   "guided cone of directions), 'auto' (manifold below 4 degrees of light radius, "
                   "cone above; 10 degrees without --light-guide) or 'off' (only paths that refract "
                   "out into the light's disc find it, no light guide either; same image, more noise). A delta light always uses 'manifold'. An "
                   "environment image is importance-sampled through the boundary by the walk "
                   "('off' turns that off too)")
        ->capture_default_str();
    cmd.add_option("--light-chain", f.light_chain,
                   "The specular chains through a refracting boundary along which the lights are "
                   "estimated: '1' = one refraction out, '2' = also one internal reflection before it "
                   "(same image; more work per sample, less noise from light that leaves after a bounce "
                   "off the inside), 'auto' = '2' for a delta light (which nothing else reaches along "
                   "that chain, estimated at a small share of the vertices, each estimate weighed up: "
                   "the same image at a fraction of the cost); for a disc light the light guide's second chain, or without the guide "
                   "'2' under 10 degrees in radius unless --light-nee is 'cone'; '1' = neither")
        ->capture_default_str();
    cmd.add_option("--env-share", j.settings.integrator.environment_share,
                   "The share of medium vertices at which an environment image is estimated through a "
                   "refracting boundary (same image; each estimate weighs 1/share, and paths that meet the "
                   "sky are weighed against share times its density): the walk costs many path steps, and "
                   "paths find much of a sky by themselves; 1: at every vertex")
        ->capture_default_str();
    cmd.add_option("--light-share", j.settings.integrator.light_share,
                   "The share of a path's later medium vertices (from its third scattering) at which the "
                   "directional light is estimated through a refracting boundary, picked systematically along "
                   "the path (same image; each estimate weighs 1/share, and paths that meet the light are "
                   "weighed against share times its density); 1: at every vertex")
        ->capture_default_str();
    cmd.add_option("--light-guide", j.settings.integrator.light_guide,
                   "For a disc light behind a refracting boundary, trace the light into the object before "
                   "the render and record from which directions it arrives in each cell (straight in, "
                   "after a reflection inside, after a reflection off the outside of another part); half "
                   "the one-refraction next-event directions are drawn from it (under 'auto' 0.8 of them "
                   "for a light of 15 degrees or more), and all of the two other chains' (same image, less "
                   "noise from light that comes in by faces the other estimators do not aim at); false: "
                   "without it")
        ->capture_default_str();
    group_from(cmd, first, "Rendering");
}

// Boundary, camera, lights and sampling: shared by `render` and the pipeline.
void add_scene_flags(CLI::App& cmd, RenderFlags& f, const std::string& seed_flag = "--seed") {
    add_boundary_flags(cmd, f);
    add_camera_flags(cmd, f);
    add_light_flags(cmd, f);
    add_rendering_flags(cmd, f, seed_flag);
}

// Turns the text flags into the job's values (throws jade::Error naming the flag).
void resolve_flags(RenderFlags& f) {
    jade::RenderJob& j = f.job;
    j.interface.mode = jade::parse_boundary_mode(f.boundary);
    j.settings.integrator.light_through_boundary = jade::parse_light_through_boundary(f.light_nee);
    j.settings.integrator.light_chain = jade::parse_light_chain(f.light_chain);
    if (!f.sphere.empty()) {
        glm::vec3 c;
        float r = 0.f;
        if (!jade::parse_sphere(f.sphere, c, r))
            throw jade::Error("--sphere expects x,y,z,r with r > 0, not '" + f.sphere + "'");
        j.sphere = std::array<float, 4>{c.x, c.y, c.z, r};
        if (j.mesh == f.job_mesh) j.mesh.clear();  // beside a --job, it replaces the job's mesh
    } else if (j.sphere && !j.mesh.empty() && j.mesh != f.job_mesh) {
        j.sphere.reset();  // a --mesh beside a --job replaces the job's sphere
    }
    if (f.sigma_s.given()) j.sigma_s = f.sigma_s.value("--sigma-s");
    if (f.sigma_a.given()) j.sigma_a = f.sigma_a.value("--sigma-a");
    if (f.ks.given()) {
        const glm::vec3 k = f.ks.value("--ks");
        j.ks = std::array<float, 3>{k.x, k.y, k.z};
    }
    if (f.contrast.given()) {
        const glm::vec3 g = f.contrast.value("--contrast");
        j.contrast = std::array<float, 3>{g.x, g.y, g.z};
    }
    if (f.vdb_albedo.given()) j.density.albedo = f.vdb_albedo.value("--vdb-albedo");
    if (f.origin.given()) j.camera_origin = f.origin.value("--camera-origin");
    if (f.target.given()) {
        j.camera_target = f.target.value("--camera-target");
        j.camera_target_given = true;
    }
    if (f.up.given()) j.camera_up = f.up.value("--camera-up");
    if (f.light_dir.given()) j.light_direction = f.light_dir.value("--light-dir");
    if (f.light_dir.given() && !j.light_file.empty())
        throw jade::Error("--light-file sets the light's direction: it cannot be combined with --light-dir");
}

// The piece a render's --samples and --pixels ask for, if any.
std::optional<jade::PieceRange> piece_of(const RenderFlags& f) {
    if (f.samples.empty() && f.pixels.empty() && f.piece_of.empty()) return std::nullopt;
    if (!f.piece_of.empty()) {
        if (!f.samples.empty() || !f.pixels.empty()) throw jade::Error("--piece replaces --samples and --pixels");
        return jade::parse_piece_of(f.piece_of, f.job);
    }
    jade::PieceRange r;
    r.samples = f.samples.empty() ? jade::SampleRange{0, f.job.settings.spp} : jade::parse_sample_range(f.samples);
    r.pixels = f.pixels.empty() ? jade::PixelBounds{0, 0, f.job.width, f.job.height}
                                : jade::parse_pixel_bounds(f.pixels);
    return r;
}

int run_render(RenderFlags& f) {
    resolve_flags(f);
    jade::RenderJob& j = f.job;
    const std::optional<jade::PieceRange> piece = piece_of(f);

    const jade::Stopwatch total;
    jade::RenderJobResult r;
    {
        const std::size_t pixels = piece ? std::size_t(piece->pixels.x1 - piece->pixels.x0) *
                                               std::size_t(piece->pixels.y1 - piece->pixels.y0)
                                         : std::size_t(j.width) * j.height;
        const int spp = piece ? piece->samples.last - piece->samples.first : j.settings.spp;
        jade::Progress progress(piece ? "render piece" : "render", pixels * std::size_t(spp), j.settings.time_limit);
        r = jade::run_render_job(j, &progress, nullptr, piece ? &*piece : nullptr);
    }
    for (const auto& w : r.warnings) std::fprintf(stderr, "jaderender: warning: %s\n", w.c_str());
    const jade::RenderResult& rr = r.render;
    const jade::PassRecord& last = rr.passes.back();
    double samples = double(j.width) * j.height * last.mean_spp;
    if (piece) {
        const jade::PixelBounds& b = piece->pixels;
        samples = double(b.x1 - b.x0) * (b.y1 - b.y0) * last.spp;
        std::printf("render piece: samples %d:%d of %d, pixels %d:%d,%d:%d of %dx%d in %.2f s; estimated relative "
                    "error of the piece alone %s",
                    piece->samples.first, piece->samples.last, j.settings.spp, b.x0, b.x1, b.y0, b.y1, j.width,
                    j.height, rr.seconds, jade::format_relative_error(last.estimated_error).c_str());
    } else {
        std::printf("render: %dx%d, %s in %.2f s (stopped by %s); estimated relative error %s", j.width,
                    j.height, jade::format_spp(last).c_str(), rr.seconds, rr.stopped_by.c_str(),
                    jade::format_relative_error(last.estimated_error).c_str());
    }
    if (last.rmse >= 0) std::printf(", RMSE %.5f, relMSE %.3g vs reference", last.rmse, last.rel_mse);
    std::printf("\n  medium: %s (%s)\n", r.medium_description.c_str(),
                jade::format_megabytes(double(r.medium_bytes)).c_str());
    std::printf("  %.3g M samples/s, %.3g M path vertices/s; collisions %.3g M real, %.3g M null\n",
                samples / rr.seconds / 1e6, double(rr.counters.vertices()) / rr.seconds / 1e6,
                double(rr.counters.real_collisions) / 1e6, double(rr.counters.null_collisions) / 1e6);
    if (rr.counters.sphere_walks > 0)
        std::printf("  stiff medium: %.3g M walks through spheres (%.2f a path), each many collisions at "
                    "once; their tables took %.2f s and %s\n",
                    double(rr.counters.sphere_walks) / 1e6,
                    double(rr.counters.sphere_walks) / double(rr.counters.paths), rr.setup_seconds,
                    jade::format_megabytes(double(rr.sphere_exit_bytes)).c_str());
    if (rr.counters.manifold_walks > 0)
        std::printf("  light through the boundary: %.3g M manifold walks, %.1f%% found no specular "
                    "chain (most have none: beyond the critical angle)%s\n",
                    double(rr.counters.manifold_walks) / 1e6,
                    100.0 * double(rr.counters.manifold_failures) / double(rr.counters.manifold_walks),
                    j.light_radius_degrees > 0.f ? "" : "; a delta light's missed paths stay dark");
    if (rr.counters.manifold_probes_ended > 0)
        std::printf("  %.3g M more walks ended by roulette after their probe found the surface far "
                    "(their light weighed up in the walks that went on)\n",
                    double(rr.counters.manifold_probes_ended) / 1e6);
    if (rr.counters.capped_paths > 0)
        std::printf("  BIAS: %llu of %llu paths were cut at --max-depth %d\n",
                    (unsigned long long)rr.counters.capped_paths,
                    (unsigned long long)rr.counters.paths, j.settings.integrator.max_depth);
    std::printf("  loading %.2f s, total %.2f s, peak memory %s\n", r.load_seconds, total.seconds(),
                jade::format_megabytes(double(jade::peak_rss_bytes())).c_str());
    for (const auto& file : r.written) std::printf("  wrote %s\n", file.c_str());
    return 0;
}

struct MergeFlags {
    std::vector<std::string> pieces;
    std::string out, png = "auto", job;
    int split = 0;
};

void add_merge_flags(CLI::App& cmd, MergeFlags& m) {
    cmd.add_option("pieces", m.pieces, "Piece files written by `render --samples/--pixels` (e.g. out/render.part-*.exr)");
    cmd.add_option("--job", m.job, "With --split N: merge the N pieces `render --job FILE --piece I/N` wrote");
    cmd.add_option("--split", m.split, "The number of pieces N of `render --piece I/N` (with --job)");
    cmd.add_option("--out", m.out, "Output .exr (default: the job's --out)");
    cmd.add_option("--png", m.png, "sRGB PNG ('auto': beside --out; '' = none)")->capture_default_str();
}

int run_merge(const MergeFlags& m) {
    const jade::Stopwatch total;
    std::vector<std::string> pieces = m.pieces;
    if (m.job.empty() != (m.split == 0)) throw jade::Error("merge: --job and --split go together");
    if (!m.job.empty()) {
        if (!pieces.empty()) throw jade::Error("merge: give piece files or --job with --split, not both");
        if (m.split < 1) throw jade::Error("--split must be at least 1");
        pieces = jade::split_piece_paths(jade::load_job(m.job), m.split, m.out);
    }
    if (pieces.empty()) throw jade::Error("merge: give the piece files, or --job and --split");
    const jade::MergeResult r = jade::merge_render_pieces(pieces, m.out, m.png);
    std::printf("merge: %d pieces of %dx%d, %d spp (seed %llu): estimated relative error %s; reading %.2f s, "
                "merging %.3f s, total %.2f s; the pieces rendered for %.1f s in all\n",
                r.pieces, r.job.width, r.job.height, r.job.settings.spp, (unsigned long long)r.job.settings.seed,
                jade::format_relative_error(r.film.estimated_relative_error()).c_str(), r.read_seconds,
                r.merge_seconds, total.seconds(), r.piece_seconds);
    for (const auto& file : r.written) std::printf("  wrote %s\n", file.c_str());
    return 0;
}

struct BatchFlags {
    std::string manifest;
    int index = -1;
    bool count = false;
    std::string summary = "summary.csv", sheet = "contact-sheet.png";
};

void add_batch_commands(CLI::App& app, BatchFlags& b, CLI::App*& batch, CLI::App*& summary) {
    batch = app.add_subcommand(
        "batch", "Run entry --index of a manifest of fits (JSON or CSV: photo, mask, mesh, out, flags), as one "
                 "task of a cluster's array job");
    batch->add_option("manifest", b.manifest, "The manifest (.json or .csv)")->required();
    batch->add_option("--index", b.index, "The entry to run, from 0 (e.g. $SLURM_ARRAY_TASK_ID)");
    batch->add_flag("--count", b.count, "Print the number of entries and exit");
    summary = app.add_subcommand(
        "summary", "Gather a manifest's report.json files into one CSV table and its compare.png files into a "
                   "contact sheet");
    summary->add_option("manifest", b.manifest, "The manifest (.json or .csv)")->required();
    summary->add_option("--out", b.summary, "The table (CSV)")->capture_default_str();
    summary->add_option("--sheet", b.sheet, "The contact sheet (PNG; '' = none)")->capture_default_str();
}

int run_summary(const BatchFlags& b) {
    const jade::BatchManifest m = jade::load_manifest(b.manifest);
    jade::require_output_folder(b.summary);
    if (!b.sheet.empty()) jade::require_output_folder(b.sheet);
    const jade::BatchSummary s = jade::write_batch_summary(m, b.summary);
    if (!b.sheet.empty()) jade::write_contact_sheet(m, b.sheet);
    std::printf("summary: %d of %zu entries done, %d missing or unreadable; wrote %s%s%s\n", s.done,
                m.entries.size(), s.missing, b.summary.c_str(), b.sheet.empty() ? "" : " and ", b.sheet.c_str());
    return 0;
}

struct PipelineFlags {
    VolumeOptions volume;
    RenderFlags scene;
    std::string out_dir, fit = "contrast";
    Vec3Flag ks_start, contrast_start;
    jade::PipelineOptions options;
};

void add_pipeline_flags(CLI::App& app, PipelineFlags& p) {
    add_volume_flags(app, p.volume, /*photo_required=*/false);
    std::size_t first = app.get_options().size();
    app.add_option("--mesh", p.scene.job.mesh, "The object's surface (.obj, .gltf, .glb)");
    app.add_option("--out", p.out_dir, "Output folder (default: <photo name>-jaderender)");
    app.add_option("--volume", p.options.volume,
                   "Fit this jaderender .vdb's k_s instead of building a volume from the photo");
    app.add_flag("--flat", p.scene.job.flat_normals, "Shade the boundary with face normals");
    app.add_flag("--allow-open", p.scene.job.allow_open, "Use a mesh with many open edges anyway");
    app.add_flag("--z-up", p.options.vdb_z_up,
                 "Write volume.vdb's grids Z-up (Blender) rather than Y-up (glTF, Houdini); jaderender reads both");
    app.add_option("--vdb-color", p.options.vdb_color_name,
                   "Name of volume.vdb's albedo grid: 'color' (Blender) or 'Cd' (Houdini)")
        ->check(CLI::IsMember({"color", "Cd"}))
        ->capture_default_str();
    group_from(app, first, "Object and output");
    add_scene_flags(app, p.scene, "--render-seed");
    jade::PipelineOptions& o = p.options;
    first = app.get_options().size();
    app.add_option("--fit", p.fit, "What the fit matches: 'contrast' (k_s and contrast per channel, and where "
                                   "needed the density scale, for the photo's brightness A and spread S), 'bisect' (k_s for A: bracket, then narrow the bracket), "
                                   "'step' (k_s for A in the paper's 0.01 steps) or 'none'")
        ->capture_default_str();
    app.add_option("--contrast", p.contrast_start.text,
                   "Contrast of the levels about their mean, r,g,b (0..16; 1 = the paper's levels): where "
                   "--fit contrast starts, or the one used by the other fits (default: 1, or that of --volume)");
    app.add_option("--fit-density", o.fit.fit_density,
                   "--fit contrast may raise --density-scale (light travels less far between the veins, which "
                   "then stay sharper) where a channel would need a contrast above 4, beyond which more and "
                   "more voxels clip; false: keep --density-scale")
        ->capture_default_str();
    app.add_option("--ks", p.ks_start.text, "k_s to start the fit from (or to use with --fit none), r,g,b "
                                            "(default: 0, or the stored k_s of --volume)");
    app.add_option("--fit-width", o.fit.width, "Width of the fitting renders (0 = a quarter of --width)")
        ->capture_default_str();
    app.add_option("--fit-spp", o.fit.spp, "Samples per pixel of the fitting renders (0 = doubled from " +
                                           std::to_string(jade::kFirstFitSpp) +
                                           " until A's standard error is below --fit-noise and the "
                                           "estimated relative error below --fit-error)")
        ->capture_default_str();
    app.add_option("--fit-noise", o.fit.noise, "Standard error of A (gray levels) the fitting renders must reach")
        ->capture_default_str();
    app.add_option("--fit-error", o.fit.error,
                   "Estimated relative error (per pixel) the fitting renders must reach")
        ->capture_default_str();
    app.add_option("--fit-spp-max", o.fit.spp_max, "Most samples per pixel a fitting render doubles to")
        ->capture_default_str();
    app.add_option("--fit-spread-spp", o.fit.spread_spp,
                   "Samples per pixel of the final-size renders --fit contrast reads the material's spread "
                   "S_material from, two a step (0 = as many samples per image as a fitting render, at least " +
                       std::to_string(jade::kMinSpreadSpp) + ", raised " + std::to_string(jade::kMaxSpreadSppGain) +
                       " times where a faint stone's spread hides in their noise and that many would show it; else "
                       "the fit leaves the contrast and warns, naming a count that would do); a count is kept as "
                       "given")
        ->capture_default_str();
    app.add_option("--fit-max-renders", o.fit.max_renders, "Most fitting renders")->capture_default_str();
    app.add_option("--final-match", o.final_match,
                   "After the fit, foresee A at the final render's size (the fitting renders are smaller, and A "
                   "falls with size): from the fit's own renders at that size under --fit contrast, else from "
                   "renders at both sizes with a quarter of the final samples (at least 64); where a channel is "
                   "foreseen 0.4 levels off or more, correct its k_s before the final render; false: keep the "
                   "fitted k_s")
        ->capture_default_str();
    app.add_flag("--measure-material", o.measure_material,
                 "Also render the fitted volume and its shading (the mean medium) in two halves each and report "
                 "the material's S, D and structure against the photo, shading and noise taken out (about two "
                 "more final renders)");
    app.add_option("--ks-max", o.fit.k_max, "Largest k_s the fit tries")->capture_default_str();
    app.add_option("--exposure", o.fit.exposure, "Render-to-photo exposure factor before the sRGB encoding "
                                             "(0 = the middle of the range where every channel can reach the photo, from the "
                                             "renders at both k_s bounds)")
        ->capture_default_str();
    group_from(app, first, "Fit");
}

int run_pipeline(PipelineFlags& p) {
    if (p.volume.photo.empty() || p.scene.job.mesh.empty())
        throw jade::Error("give --photo and --mesh (the whole fit), or a command: volume, render, merge, batch, "
                          "summary, bench (see --help)");
    resolve_flags(p.scene);
    jade::PipelineOptions& o = p.options;
    o.photo = p.volume.photo;
    o.mask = p.volume.mask;
    o.photo_span = p.volume.photo_span;
    o.noise = p.volume.noise;
    // 'auto': the first fit's volume unsharpened, the fit choosing after it.
    o.sharpen_from_fit = p.volume.sharpen == "auto";
    o.noise.sharpen = o.sharpen_from_fit ? 0.0 : sharpen_amount(p.volume.sharpen);
    o.structure = jade::parse_structure_mode(p.volume.structure);
    o.match = jade::parse_match_mode(p.volume.match);
    o.optics = p.volume.optics;
    o.optics.extinction = jade::parse_extinction(p.volume.extinction);
    if (p.ks_start.given()) {
        const glm::vec3 k = p.ks_start.value("--ks");
        o.fit.ks_start = std::array<double, 3>{k.x, k.y, k.z};
    }
    if (p.contrast_start.given()) {
        const glm::vec3 g = p.contrast_start.value("--contrast");
        o.fit.contrast_start = std::array<double, 3>{g.x, g.y, g.z};
    }
    o.fit.method = jade::parse_fit_method(p.fit);
    o.out_dir = p.out_dir;
    o.render = p.scene.job;
    o.progress = true;
    const jade::PipelineResult r = jade::run_pipeline(o);
    jade::print_pipeline_summary(o, r);
    return 0;
}

struct BenchCommands {
    CLI::App *bench, *volume, *render, *fidelity, *stiff, *convergence;
};

// `jaderender bench volume|render|fidelity|stiff|convergence` and their flags.
BenchCommands add_bench_commands(CLI::App& app, jade::VolumeBenchOptions& bench, jade::RenderBenchOptions& rbench,
                                 jade::FidelityBenchOptions& fbench, jade::StiffBenchOptions& sbench,
                                 jade::ConvergenceBenchOptions& cbench) {
    auto* cmd = app.add_subcommand(
        "bench", "Benchmarks: time, throughput, error against time and peak memory");
    cmd->require_subcommand(1);
    auto* bench_volume = cmd->add_subcommand(
        "volume", "The volume's stages: noise + matching, .vdb write and read");
    bench_volume->add_option("--resolution", bench.resolution, "Voxels along each side")
        ->capture_default_str();
    bench_volume->add_option("--photo", bench.photo,
                             "Photo to match (default: a built-in synthetic stone)");
    bench_volume->add_option("--repeats", bench.repeats, "Runs per stage; the best is reported")
        ->capture_default_str();
    bench_volume->add_option("--scratch", bench.scratch_dir,
                             "Folder for the temporary .vdb (default: the system's temp folder)");
    auto* bench_render = cmd->add_subcommand(
        "render", "Progressive rendering of the material volume in a mesh until a target error");
    bench_render->add_option("--photo", rbench.photo, "Photo (default: a built-in synthetic stone)");
    bench_render->add_option("--mesh", rbench.mesh, "Mesh (default: a built-in sphere)");
    bench_render->add_option("--resolution", rbench.resolution, "Voxels along each side")
        ->capture_default_str();
    bench_render->add_option("--width", rbench.width, "Image width")->capture_default_str();
    bench_render->add_option("--height", rbench.height, "Image height")->capture_default_str();
    bench_render->add_option("--target-error", rbench.target_error,
                             "Estimated relative error to stop at")
        ->capture_default_str();
    bench_render->add_option("--max-seconds", rbench.max_seconds, "Time budget")
        ->capture_default_str();

    auto* fidelity = cmd->add_subcommand(
        "fidelity", "The paper's method and the default on one photo and mesh: A, S, D (whole render and "
                    "material), structure, renders and seconds, and D(default)/D(paper)");
    fidelity->add_option("--photo", fbench.photo, "Photograph of the material")->required();
    fidelity->add_option("--mask", fbench.mask, "Mask image (white = object)");
    fidelity->add_option("--photo-span", fbench.photo_span,
                         "How many of the object's sizes the photo's width spans (both methods)")
        ->capture_default_str();
    fidelity->add_option("--mesh", fbench.mesh, "The object's surface")->required();
    fidelity->add_option("--out", fbench.out_dir, "Folder for both results (default/ and paper/)")
        ->capture_default_str();
    fidelity->add_option("--resolution", fbench.resolution, "Voxels along each side")->capture_default_str();
    fidelity->add_option("--width", fbench.width, "Final render width")->capture_default_str();
    fidelity->add_option("--veins", fbench.veins,
                         "The default with --veins (the estimate searches them; the paper's method has none)")
        ->capture_default_str();
    fidelity->add_option("--structure", fbench.structure,
                         "The default's structure: 'photo' (its own default), 'exemplar' or 'fbm' (the paper's "
                         "method keeps the fBm)")
        ->capture_default_str();
    fidelity->add_option("--height", fbench.height, "Final render height")->capture_default_str();
    fidelity->add_option("--spp", fbench.spp,
                         "Samples per pixel of both final renders and of the renders measuring their material")
        ->capture_default_str();
    fidelity->add_option("--seeds", fbench.seeds,
                         "Run both methods with noise and render seeds 1..N and give D's ratio over them")
        ->capture_default_str();
    fidelity->add_option("--densities", fbench.densities,
                         "Density scales, e.g. 5,20,60,200,600: the default's fitted volume (seed 1) as its mean "
                         "medium at each, and under its shading the photo's own stone's D and the least any "
                         "material reaches, over the paper's D (one shading render each)")
        ->delimiter(',');
    auto* stiff = cmd->add_subcommand(
        "stiff", "Stiff media: the white furnace from sigma_t 1 to 1e5, with and without sphere walks");
    stiff->add_option("--width", sbench.width, "Image width and height")->capture_default_str();
    stiff->add_option("--spp", sbench.spp, "Samples per pixel a case")->capture_default_str();
    stiff->add_option("--seconds", sbench.seconds, "Time budget a case")->capture_default_str();
    stiff->add_option("--max-sigma-t", sbench.max_sigma_t, "Largest sigma_t (per unit length)")
        ->capture_default_str();
    auto* convergence = cmd->add_subcommand(
        "convergence", "A render's true error against samples and seconds, measured across independent batches, "
                       "beside the film's own estimate");
    convergence->add_option("--job", cbench.job, "The render: a job document or a pipeline's report.json")->required();
    convergence->add_option("--batches", cbench.batches, "Independent batches (a power of 2)")->capture_default_str();
    convergence->add_option("--batch-spp", cbench.batch_spp, "Samples per pixel of a batch")->capture_default_str();
    return {cmd, bench_volume, bench_render, fidelity, stiff, convergence};
}

// Parses the command line: -1 to go on, else the exit code (0 after --help
// or --version, 2 for a bad flag).
int parse_flags(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "jaderender: error: %s (see --help)\n", jade::Error(e.what()).what());
        return 2;
    }
    return -1;
}

}  // namespace

namespace {

int run_command(int argc, char** argv);

// `batch MANIFEST --index I`: entry I's fit, parsed and run as if its flags
// had been given to jaderender.
int run_batch_entry(const BatchFlags& b) {
    const jade::BatchManifest m = jade::load_manifest(b.manifest);
    if (b.count) {
        std::printf("%zu\n", m.entries.size());
        return 0;
    }
    if (b.index < 0) throw jade::Error("batch: give --index I (0 to " + std::to_string(m.entries.size() - 1) +
                                       ") or --count");
    std::vector<std::string> args = jade::entry_arguments(m, b.index);
    args.insert(args.begin(), "jaderender");
    jade::create_entry_parent(m, b.index);
    std::printf("batch: entry %d of %zu: %s on %s -> %s\n", b.index, m.entries.size(),
                m.entries[std::size_t(b.index)].photo.c_str(), m.entries[std::size_t(b.index)].mesh.c_str(),
                m.entries[std::size_t(b.index)].out.c_str());
    std::fflush(stdout);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    return run_command(int(args.size()), argv.data());
}

// The top level's version flag and --help footer (an example that works).
void describe_app(CLI::App& app) {
    app.set_version_flag("--version", std::string(JADE_VERSION));
    app.footer("Example: fit the demo photo onto the vase, outputs in out/onyx002/\n"
               "  jaderender --photo data/photos/ambientcg_Onyx002_512_diff.jpg "
               "--mesh data/meshes/greek-vase-01.glb --out out/onyx002\n"
               "then render the fitted volume on another mesh:\n"
               "  jaderender render --volume out/onyx002/volume.vdb --mesh data/meshes/spot-cow.obj "
               "--out cow.exr");
}

// `jaderender volume` and its flags.
CLI::App* add_volume_command(CLI::App& app, VolumeOptions& vol) {
    CLI::App* volume_cmd = app.add_subcommand(
        "volume", "Build the material volume from a photo (noise -> colour matching -> "
                  "coefficients) and write it as .vdb");
    add_volume_flags(*volume_cmd, vol);
    volume_cmd->add_option("--out", vol.out, "Output .vdb file")->required();
    volume_cmd->add_option("--contrast", vol.contrast.text,
                           "Contrast of the levels about their mean, r,g,b (0..16; default 1, the paper's)");
    volume_cmd->add_flag("--z-up", vol.z_up, "Write the grids Z-up (Blender) rather than Y-up (glTF, Houdini)");
    volume_cmd->add_option("--vdb-color", vol.color_name, "Name of the albedo grid: 'color' (Blender) or 'Cd' (Houdini)")
        ->check(CLI::IsMember({"color", "Cd"}))
        ->capture_default_str();
    volume_cmd->add_option("--preview", vol.preview,
                           "Also write the middle slice of the matched noise as an image");
    return volume_cmd;
}

int run_command(int argc, char** argv) {
    CLI::App app{"jaderender: Monte Carlo rendering and fitting of heterogeneous translucent "
                 "materials (jade, marble) from one photograph"};
    describe_app(app);
    app.require_subcommand(0, 1);
    // No fallthrough: a top-level (fitting) flag given after a subcommand is
    // an error, not silently taken by the pipeline that does not run.

    // --threads is accepted by every command, before or after its name.
    int threads = 0;
    auto add_threads = [&threads](CLI::App& cmd) {
        cmd.add_option("--threads", threads,
                       "Worker threads (0 = all cores); results do not depend on it")
            ->check(CLI::Range(0, 4096))
            ->capture_default_str();
    };
    add_threads(app);

    VolumeOptions vol;
    CLI::App* volume_cmd = add_volume_command(app, vol);

    RenderFlags render_flags;
    if (!preload_job(argc, argv, render_flags)) return 2;
    auto* render_cmd = app.add_subcommand(
        "render", "Render a medium (a saved volume, a foreign .vdb or a homogeneous one) inside a "
                  "mesh's dielectric boundary");
    add_medium_flags(*render_cmd, render_flags);
    add_scene_flags(*render_cmd, render_flags);

    MergeFlags merge;
    auto* merge_cmd = app.add_subcommand(
        "merge", "Merge the pieces of a split render (render --samples/--pixels) into its image, "
                 "bit-identical to one render of all the samples");
    add_merge_flags(*merge_cmd, merge);

    BatchFlags batch;
    CLI::App *batch_cmd = nullptr, *summary_cmd = nullptr;
    add_batch_commands(app, batch, batch_cmd, summary_cmd);

    PipelineFlags pipeline;
    add_pipeline_flags(app, pipeline);

    jade::VolumeBenchOptions bench;
    jade::RenderBenchOptions rbench;
    jade::FidelityBenchOptions fbench;
    jade::StiffBenchOptions sbench;
    jade::ConvergenceBenchOptions cbench;
    const BenchCommands benches = add_bench_commands(app, bench, rbench, fbench, sbench, cbench);

    for (CLI::App* cmd : {volume_cmd, render_cmd, merge_cmd, batch_cmd, summary_cmd, benches.bench, benches.volume,
                          benches.render, benches.fidelity, benches.stiff, benches.convergence})
        add_threads(*cmd);

    if (const int code = parse_flags(app, argc, argv); code >= 0) return code;

    std::unique_ptr<tbb::global_control> thread_limit;
    if (threads > 0)
        thread_limit = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    try {
        if (app.get_subcommands().empty()) return run_pipeline(pipeline);
        if (*volume_cmd) return run_volume(vol);
        if (*render_cmd) return run_render(render_flags);
        if (*merge_cmd) return run_merge(merge);
        if (*batch_cmd) return run_batch_entry(batch);
        if (*summary_cmd) return run_summary(batch);
        if (*benches.volume) return jade::run_volume_benchmark(bench);
        if (*benches.render) return jade::run_render_benchmark(rbench);
        if (*benches.fidelity) return jade::run_fidelity_benchmark(fbench);
        if (*benches.stiff) return jade::run_stiff_benchmark(sbench);
        if (*benches.convergence) return jade::run_convergence_benchmark(cbench);
    } catch (const jade::Error& e) {
        std::fprintf(stderr, "jaderender: error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "jaderender: internal error: %s\n", jade::Error(e.what()).what());
        return 3;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    jade::install_interrupt_cleanup();
    return run_command(argc, argv);
}
