#include "jade/bench.h"

#include "jade/atomic_file.h"
#include "jade/material_volume.h"
#include "jade/photo.h"
#include "jade/random.h"
#include "jade/report.h"
#include "jade/vdb_io.h"

#include <tbb/info.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>

namespace jade {

namespace {

// 512x512 stone: grey body with 10% rose veins, so joint matching has two
// colour families to keep apart.
Photo builtin_photo() {
    Photo p;
    p.path = "(built-in synthetic stone)";
    p.width = p.height = 512;
    SplitMix64 rng(2016);
    for (int i = 0; i < 512 * 512; ++i) {
        const int d = int(rng.below(31)) - 15;
        p.levels.push_back(rng.uniform() < 0.1
                               ? Rgb8{std::uint8_t(200 + d / 2), std::uint8_t(90 + d), std::uint8_t(100 + d)}
                               : Rgb8{std::uint8_t(150 + d), std::uint8_t(150 + d), std::uint8_t(145 + d)});
        p.foreground.push_back(1);
    }
    return p;
}

double best_of(int repeats, const std::function<void()>& stage) {
    double best = 1e300;
    for (int i = 0; i < std::max(1, repeats); ++i) {
        Stopwatch sw;
        stage();
        best = std::min(best, sw.seconds());
    }
    return best;
}

}  // namespace

int run_volume_benchmark(const VolumeBenchOptions& o) {
    const Photo photo = o.photo.empty() ? builtin_photo() : load_photo(o.photo);
    NoiseParams noise;
    noise.resolution = o.resolution;
    noise.validate();
    const double voxels = double(o.resolution) * o.resolution * o.resolution;

    std::printf("volume benchmark: %d^3 voxels, photo %s, %d threads, best of %d\n", o.resolution,
                photo.path.c_str(), tbb::info::default_concurrency(), o.repeats);
    std::printf("%-28s %10s %14s %12s\n", "stage", "seconds", "Mvoxels/s", "peak RSS");

    MaterialVolume vol;
    for (MatchMode mode : {MatchMode::PerChannel, MatchMode::Joint}) {
        const double t = best_of(o.repeats, [&] {
            vol = MaterialVolume{};  // measure one volume's memory, not two
            vol = build_material_volume(photo, noise, mode, OpticalParams{});
        });
        std::printf("%-28s %10.3f %14.1f %12s\n",
                    (std::string("noise + matching (") + to_string(mode) + ")").c_str(), t,
                    voxels / t / 1e6, format_megabytes(double(peak_rss_bytes())).c_str());
    }

    const std::string dir = o.scratch_dir.empty() ? std::filesystem::temp_directory_path().string()
                                                  : o.scratch_dir;
    const std::string path = (std::filesystem::path(dir) / "jaderender-bench.vdb").string();
    const double tw = best_of(o.repeats, [&] { write_material_vdb(path, vol); });
    const double size = double(file_size(path));
    std::printf("%-28s %10.3f %14.1f %12s   (file %s)\n", "vdb write", tw, voxels / tw / 1e6,
                format_megabytes(double(peak_rss_bytes())).c_str(), format_megabytes(size).c_str());
    MaterialVolume back;
    const double tr = best_of(o.repeats, [&] { back = read_material_vdb(path); });
    std::printf("%-28s %10.3f %14.1f %12s\n", "vdb read", tr, voxels / tr / 1e6,
                format_megabytes(double(peak_rss_bytes())).c_str());
    std::filesystem::remove(path);
    std::printf("round trip exact: %s\n", back.levels == vol.levels ? "yes" : "NO");
    return back.levels == vol.levels ? 0 : 1;
}

}  // namespace jade
