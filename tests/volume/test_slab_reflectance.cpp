// The Kubelka–Munk slab against its closed forms and its own adding rule,
// and its coefficients against Chandrasekhar's half-space.

#include "jade/core/chandrasekhar.h"
#include "jade/volume/slab_reflectance.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jade;

TEST_CASE("Kubelka-Munk slab: the limits without absorption and without scattering", "[slab]") {
    for (double sd : {0.01, 1.0, 30.0}) {
        const SlabReflectance s = kubelka_munk_slab({0.0, sd}, 1.0);
        CHECK(s.R == Approx(sd / (1 + sd)).epsilon(1e-12));
        CHECK(s.R + s.T == Approx(1.0).epsilon(1e-12));  // nothing absorbs
    }
    const SlabReflectance glass = kubelka_munk_slab(kubelka_munk_coefficients(0.0, 0.7, 0.0), 2.0);
    CHECK(glass.R == 0.0);
    CHECK(glass.T == Approx(std::exp(-2 * 0.7 * 2.0)).epsilon(1e-12));  // diffuse light: paths 2d long
}

TEST_CASE("Kubelka-Munk slab: two slabs stacked are the slab of their summed thickness", "[slab]") {
    // The adding rule of two layers with interreflection between them:
    // R = R1 + T1² R2 / (1 − R1 R2), T = T1 T2 / (1 − R1 R2) — an identity of
    // the two-flux equations, not of this code's sinh/cosh form.
    const KubelkaMunk km{0.3, 2.5};
    for (double d1 : {0.05, 0.7, 3.0})
        for (double d2 : {0.2, 1.9}) {
            const SlabReflectance a = kubelka_munk_slab(km, d1), b = kubelka_munk_slab(km, d2);
            const SlabReflectance both = kubelka_munk_slab(km, d1 + d2);
            const double denom = 1 - a.R * b.R;
            CHECK(both.R == Approx(a.R + a.T * a.T * b.R / denom).epsilon(1e-10));
            CHECK(both.T == Approx(a.T * b.T / denom).epsilon(1e-10));
        }
}

TEST_CASE("Kubelka-Munk coefficients: a thick slab reflects what Chandrasekhar's half-space does", "[slab]") {
    for (double albedo : {0.2, 0.5, 0.9, 0.99, 0.9999}) {
        const KubelkaMunk km = kubelka_munk_coefficients(albedo, 1 - albedo, 0.0);
        const SlabReflectance thick = kubelka_munk_slab(km, 1e6);  // no overflow
        INFO("albedo " << albedo);
        CHECK(thick.R == Approx(ChandrasekharH(albedo).diffuse_albedo()).epsilon(1e-9));
        CHECK(thick.T == Approx(0.0).margin(1e-12));
        CHECK(km.K == Approx(2 * (1 - albedo)));
    }
    // The similarity relation: σ_s (1 − g) at g is σ_s(1 − g) at 0.
    const KubelkaMunk forward = kubelka_munk_coefficients(4.0, 0.1, 0.75), iso = kubelka_munk_coefficients(1.0, 0.1, 0.0);
    CHECK(forward.S == Approx(iso.S).epsilon(1e-12));
    // Without absorption S = (3/4) σ_s(1 − g), the limit of the rule as the absorption vanishes.
    CHECK(kubelka_munk_coefficients(2.0, 0.0, 0.5).S == Approx(0.75));
    CHECK(kubelka_munk_coefficients(2.0, 1e-9, 0.5).S == Approx(0.75).epsilon(2e-3));
}
