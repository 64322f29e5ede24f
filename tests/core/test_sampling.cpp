// The uniform-sphere warp against its law: equal solid angles get equal
// shares (χ² over bins of equal area in (z, φ), by Archimedes' theorem),
// unit length, and a sample that is not uniform is told apart.

#include "jade/core/sampling.h"
#include "jade/core/random.h"

#include "support/chi2.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace jade;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kZ = 16, kPhi = 16;

// Counts of directions in kZ × kPhi bins of equal solid angle.
template <class Draw>
std::vector<double> sphere_counts(int samples, Draw draw) {
    std::vector<double> counts(kZ * kPhi, 0.0);
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 w = draw();
        double phi = std::atan2(double(w.y), double(w.x));
        if (phi < 0) phi += 2 * kPi;
        const int bz = std::clamp(int((double(w.z) + 1.0) * 0.5 * kZ), 0, kZ - 1);
        const int bp = std::clamp(int(phi / (2 * kPi) * kPhi), 0, kPhi - 1);
        counts[std::size_t(bz * kPhi + bp)] += 1;
    }
    return counts;
}
}  // namespace

TEST_CASE("uniform_sphere is uniform in solid angle (chi-square)", "[sampling]") {
    const int samples = 256000;
    SampleStream rng(11, 3, 0);
    const std::vector<double> expected(kZ * kPhi, double(samples) / (kZ * kPhi));
    const std::vector<double> counts = sphere_counts(samples, [&] {
        const glm::vec3 w = uniform_sphere(rng.uniform(), rng.uniform());
        REQUIRE(std::abs(glm::length(w) - 1.f) < 1e-5f);
        return w;
    });
    int dof = 0;
    const double stat = jade_test::chi2_statistic(counts, expected, dof);
    INFO("chi2 = " << stat << " with " << dof << " dof");
    CHECK(stat < jade_test::chi2_critical_1e4(dof));

    // The test can fail: directions uniform in the polar angle θ instead
    // (too many near the poles) are rejected.
    const std::vector<double> polar = sphere_counts(samples, [&] {
        const float theta = float(kPi) * rng.uniform(), phi = float(2 * kPi) * rng.uniform();
        return glm::vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    });
    int dof_polar = 0;
    const double stat_polar = jade_test::chi2_statistic(polar, expected, dof_polar);
    CHECK(stat_polar > jade_test::chi2_critical_1e4(dof_polar));
}

TEST_CASE("systematic selection: each event with probability q, a sequence's count fixed to within one",
          "[sampling]") {
    // Over n offsets stratified in [0, 1), frac(offset + k·q) is the same
    // stratified grid rotated, so event k is selected at ⌊n·q⌋ or ⌈n·q⌉ of
    // them, for every k: its probability over a uniform offset is q. And for
    // any offset, m consecutive events hold ⌊m·q⌋ or ⌈m·q⌉ selections.
    for (const float q : {0.4f, 0.02f, 0.3f, 0.7f, 1.f}) {
        constexpr int kOffsets = 10000;
        for (const int k : {0, 1, 2, 7, 100, 12345, 999999}) {
            int selected = 0;
            for (int i = 0; i < kOffsets; ++i) selected += systematic_selected((i + 0.5f) / kOffsets, k, q);
            INFO("q " << q << ", event " << k);
            CHECK(std::abs(selected - double(q) * kOffsets) <= 1.0);
        }
        SplitMix64 rng(7);
        for (int trial = 0; trial < 200; ++trial) {
            const float offset = float(rng.uniform());
            const int first = int(rng.below(1000)), m = 1 + int(rng.below(60));
            int selected = 0;
            for (int k = first; k < first + m; ++k) selected += systematic_selected(offset, k, q);
            INFO("q " << q << ", events " << first << " to " << first + m);
            CHECK(selected >= int(std::floor(double(m) * q - 1e-9)));
            CHECK(selected <= int(std::ceil(double(m) * q + 1e-9)));
        }
    }
}
