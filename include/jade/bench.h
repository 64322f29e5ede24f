#pragma once
// Benchmarks: speed and memory of the pipeline's stages on built-in inputs,
// printed as a table. Measured here, never by timed tests.

#include <cstdint>
#include <string>

namespace jade {

struct VolumeBenchOptions {
    int resolution = 256;
    std::string photo;       // empty: a built-in synthetic two-colour stone photo
    std::string scratch_dir; // where the .vdb is written and read back (removed after)
    int repeats = 3;         // each timed stage runs this often; the best time is reported
};

// Noise + matching, the .vdb write and read: wall time per stage (best of
// `repeats`), voxels per second, file size and the process's peak memory
// after the in-memory stages and after the file stages. Returns 0.
int run_volume_benchmark(const VolumeBenchOptions& options);

}  // namespace jade
