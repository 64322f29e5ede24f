// The uniform-sphere warp against its law: equal solid angles get equal
// shares (χ² over bins of equal area in (z, φ), by Archimedes' theorem),
// unit length, and a sample that is not uniform is told apart. The elliptic
// cone's density against the solid angle itself: it integrates to 1 over
// the sphere (a quadrature on the equal-area map), and its directions fall
// in the bins of that map as its integral over each bin says.

#include "jade/core/sampling.h"
#include "jade/core/random.h"
#include "jade/core/sphere_bins.h"

#include "support/chi2.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace jade;

namespace {
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

namespace {
// The integral of f over each bin of `bins`, by the midpoint rule on
// sub × sub equal squares of the equal-area map (each of equal solid angle),
// for the bins whose centre lies within `reach` radians of `axis` (0
// elsewhere).
template <class F>
std::vector<double> bin_integrals(const SphereBins& bins, int sub, const glm::vec3& axis, float reach, F f) {
    std::vector<double> out(std::size_t(bins.count()), 0.0);
    const double cell = double(bins.solid_angle()) / double(sub * sub);
    for (int b = 0; b < bins.count(); ++b) {
        if (glm::dot(bins.direction(b, 0.5f, 0.5f), axis) < std::cos(reach)) continue;
        double sum = 0.0;
        for (int j = 0; j < sub; ++j)
            for (int i = 0; i < sub; ++i)
                sum += double(f(bins.direction(b, (float(i) + 0.5f) / float(sub), (float(j) + 0.5f) / float(sub))));
        out[std::size_t(b)] = sum * cell;
    }
    return out;
}
}  // namespace

TEST_CASE("an elliptic cone's density integrates to 1 and its directions fall where it says (chi-square)",
          "[sampling]") {
    EllipticCone cone;
    cone.axis = glm::normalize(glm::vec3(0.3f, 0.2f, 0.9f));
    glm::vec3 t, b;
    orthonormal_basis(cone.axis, t, b);
    cone.major = glm::normalize(t + 0.5f * b);
    cone.minor = glm::cross(cone.axis, cone.major);
    cone.r_major = 0.6f;  // 31° on the tangent plane: cos³θ falls to 0.63 at its end
    cone.r_minor = 0.2f;
    const SphereBins bins{64};
    const std::vector<double> mass =
        bin_integrals(bins, 32, cone.axis, 0.8f, [&](const glm::vec3& w) { return cone.pdf(w); });
    double total = 0.0;
    for (double m : mass) total += m;
    CHECK(total == Approx(1.0).epsilon(2e-3));

    const int samples = 200000;
    SampleStream rng(12, 0, 0);
    std::vector<double> counts(std::size_t(bins.count()), 0.0);
    int outside = 0;
    for (int k = 0; k < samples; ++k) {
        const glm::vec3 w = cone.sample(rng.uniform(), rng.uniform());
        if (!(cone.pdf(w) > 0.f)) ++outside;
        counts[std::size_t(bins.index(w))] += 1.0;
    }
    CHECK(outside == 0);
    std::vector<double> expected(mass.size());
    for (std::size_t i = 0; i < mass.size(); ++i) expected[i] = mass[i] * samples;
    int dof = 0;
    const double stat = jade_test::chi2_statistic(counts, expected, dof);
    INFO("chi2 = " << stat << " with " << dof << " dof");
    CHECK(stat < jade_test::chi2_critical_1e4(dof));

    // The test can fail: the same directions against a density uniform on
    // the tangent plane's ellipse (the cos³θ left out), normalised over the
    // sphere, are rejected.
    const auto flat = [&](const glm::vec3& w) { return cone.pdf(w) > 0.f ? 1.f : 0.f; };
    const std::vector<double> flat_mass = bin_integrals(bins, 32, cone.axis, 0.8f, flat);
    double flat_total = 0.0;
    for (double m : flat_mass) flat_total += m;
    for (std::size_t i = 0; i < mass.size(); ++i) expected[i] = flat_mass[i] / flat_total * samples;
    int flat_dof = 0;
    const double flat_stat = jade_test::chi2_statistic(counts, expected, flat_dof);
    CHECK(flat_stat > jade_test::chi2_critical_1e4(flat_dof));
}
