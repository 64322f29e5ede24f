// The unsharp mask on the levels (volume/sharpen.h) against the Fourier
// transform of a Gaussian: a sinusoid of f cycles per voxel comes out
// 1 + β (1 − exp(−2π² r² f²)) times as strong, its mean unchanged.

#include "jade/volume/sharpen.h"

#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

using namespace jade;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSide = 32;

std::size_t index(int x, int y, int z) { return (std::size_t(z) * kSide + y) * kSide + x; }

// A sinusoid of `period` voxels along `axis` in channel 0, constant levels
// in the others.
std::vector<Rgb8> sinusoid(int axis, double period, double amplitude) {
    std::vector<Rgb8> v(std::size_t(kSide) * kSide * kSide);
    for (int z = 0; z < kSide; ++z)
        for (int y = 0; y < kSide; ++y)
            for (int x = 0; x < kSide; ++x) {
                const int along = axis == 0 ? x : axis == 1 ? y : z;
                const double level = 128.0 + amplitude * std::sin(2.0 * kPi * (along + 0.5) / period);
                v[index(x, y, z)] = {std::uint8_t(std::lround(level)), 90, 200};
            }
    return v;
}

}  // namespace

TEST_CASE("sharpening raises a sinusoid by the Gaussian's transfer function and keeps the rest", "[sharpen]") {
    const double beta = 2.0, radius = 1.0, amplitude = 40.0;
    for (int axis = 0; axis < 3; ++axis)
        for (double period : {4.0, 8.0, 16.0}) {
            INFO("axis " << axis << ", period " << period << " voxels");
            std::vector<Rgb8> v = sinusoid(axis, period, amplitude);
            const std::array<double, 3> clipped = sharpen_levels(v, kSide, beta, radius);
            const double f = 1.0 / period;
            const double gain = 1.0 + beta * (1.0 - std::exp(-2.0 * kPi * kPi * radius * radius * f * f));
            double worst = 0.0;
            // Away from the edges (three radii), where the blur sees no repeated voxel.
            for (int z = 0; z < kSide; ++z)
                for (int y = 0; y < kSide; ++y)
                    for (int x = 0; x < kSide; ++x) {
                        const int along = axis == 0 ? x : axis == 1 ? y : z;
                        if (along < 3 || along >= kSide - 3) continue;
                        const double expected = 128.0 + gain * amplitude * std::sin(2.0 * kPi * (along + 0.5) / period);
                        worst = std::max(worst, std::abs(v[index(x, y, z)][0] - expected));
                        REQUIRE(v[index(x, y, z)][1] == 90);
                        REQUIRE(v[index(x, y, z)][2] == 200);
                    }
            // The input's rounding (half a level) times the gain, the
            // output's (half a level), and the sampled Gaussian's transfer
            // against the continuous one (below 0.001 of the amplitude).
            CHECK(worst <= 0.5 * gain + 0.5 + 0.001 * amplitude * beta);
            CHECK(clipped == std::array<double, 3>{0.0, 0.0, 0.0});
            CHECK(sharpening_warning(beta, clipped).empty());
        }
}

TEST_CASE("sharpening a step overshoots on both sides and reports the voxels it clips", "[sharpen]") {
    std::vector<Rgb8> v(std::size_t(kSide) * kSide * kSide);
    for (int z = 0; z < kSide; ++z)
        for (int y = 0; y < kSide; ++y)
            for (int x = 0; x < kSide; ++x) v[index(x, y, z)] = {std::uint8_t(x < kSide / 2 ? 0 : 255), 60, 200};
    const std::array<double, 3> clipped = sharpen_levels(v, kSide, 1.0, 1.0);
    // The voxels next to the step on either side are pushed beyond the range:
    // at least one plane each side, at most the Gaussian's reach (3 voxels).
    CHECK(clipped[0] >= 2.0 / kSide);
    CHECK(clipped[0] <= 6.0 / kSide);
    CHECK(clipped[1] == 0.0);
    CHECK(clipped[2] == 0.0);
    // More than 5 % of a channel clipped: the warning names the amount and the shares.
    const std::string warning = sharpening_warning(1.0, clipped);
    CHECK_THAT(warning, Catch::Contains("--sharpen 1 clipped"));
    CHECK_THAT(warning, Catch::Contains(std::to_string(int(std::lround(100.0 * clipped[0]))) + " %"));
    CHECK(sharpening_warning(1.0, {0.05, 0.0, 0.01}).empty());
    // Far from the step the levels are untouched.
    CHECK(v[index(2, 5, 5)][0] == 0);
    CHECK(v[index(kSide - 3, 5, 5)][0] == 255);
}

TEST_CASE("sharpening by 0 leaves the levels, and the result does not depend on the threads", "[sharpen]") {
    std::vector<Rgb8> v(std::size_t(kSide) * kSide * kSide);
    for (std::size_t i = 0; i < v.size(); ++i)
        v[i] = {std::uint8_t(i * 37 % 251), std::uint8_t(i * 11 % 241), std::uint8_t(i % 256)};
    std::vector<Rgb8> none = v;
    sharpen_levels(none, kSide, 0.0, 1.0);
    CHECK(none == v);
    std::vector<Rgb8> many = v, one = v;
    sharpen_levels(many, kSide, 1.5, 1.3);
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        sharpen_levels(one, kSide, 1.5, 1.3);
    }
    CHECK(many == one);
    CHECK(many != v);
}
