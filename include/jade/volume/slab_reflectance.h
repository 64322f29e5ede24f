#pragma once
// How much light a slab of homogeneous medium reflects and lets through
// under diffuse light: the two numbers a real-time material can show of a
// scattering stone (the pipeline's preview.glb, io/gltf_preview.h;
// docs/preview.md). Kubelka & Munk's two-flux model (1931) of a slab, with
// its coefficients chosen so that a slab of infinite thickness reflects
// exactly what Chandrasekhar's half-space does.

namespace jade {

// Kubelka–Munk coefficients per unit length: K absorbs, S scatters back.
struct KubelkaMunk {
    double K = 0, S = 0;
};

// Diffuse reflectance R and transmittance T of a slab (both of flux, for
// diffuse light in; 1 − R − T is absorbed).
struct SlabReflectance {
    double R = 0, T = 0;
};

// K = 2σ_a (diffuse light crosses a layer dz on paths 2dz long on average),
// and S such that K–M's R∞ = 1 + K/S − √((K/S)² + 2K/S) equals the exact
// diffuse albedo of an index-matched half-space of isotropic scattering
// (core/chandrasekhar.h) at the similarity-reduced albedo
// a' = σ_s(1 − g) / (σ_s(1 − g) + σ_a). Without absorption S = (3/4) σ_s(1 − g),
// the limit of the same rule as a' → 1 (the classic diffusion mapping of
// Star et al. 1988). Coefficients per world unit, g the phase function's.
KubelkaMunk kubelka_munk_coefficients(double sigma_s, double sigma_a, double g);

// The slab of thickness d (in the coefficients' length unit):
// R = sinh(bSd) / (a sinh(bSd) + b cosh(bSd)), T = b / (the same), with
// a = 1 + K/S, b = √(a² − 1); without scattering R = 0, T = e^(−Kd);
// without absorption R = Sd / (1 + Sd), T = 1 / (1 + Sd).
SlabReflectance kubelka_munk_slab(const KubelkaMunk& km, double d);

}  // namespace jade
