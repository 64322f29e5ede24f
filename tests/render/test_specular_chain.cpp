// The path classes of the light estimators (render/specular_chain.h): each
// sequence of surface events after a scattering lands in the class of the
// one estimator that makes such paths, or in none. A path weighed against an
// estimator that cannot make it loses that share of its light (a bias).
#include "jade/render/specular_chain.h"

#include <catch2/catch.hpp>

using jade::ChainTracker;
using jade::SpecularChain;

namespace {
const glm::vec3 kA(1.f, 0.f, 0.f), kB(0.f, 2.f, 0.f), kC(0.f, 0.f, 3.f);

// Surface events as Integrator::cross_surface records them.
void refract_out(ChainTracker& t, const glm::vec3& p) { t.record(p, false, false, false); }
void reflect_inside(ChainTracker& t, const glm::vec3& p) { t.record(p, false, true, true); }
void refract_in(ChainTracker& t, const glm::vec3& p) { t.record(p, true, false, true); }
}  // namespace

TEST_CASE("specular chains: no scattering known means no estimator", "[specular_chain]") {
    ChainTracker t;
    CHECK_FALSE(t.chain());
    refract_out(t, kA);
    CHECK_FALSE(t.chain());
    CHECK_FALSE(t.glint(kB).chain());
    t.scattered();
    t.lose();  // a walk through a sphere: its last scattering is unknown
    CHECK_FALSE(t.chain());
}

TEST_CASE("specular chains: the estimators' three classes and their points", "[specular_chain]") {
    ChainTracker t;
    t.scattered();
    CHECK(t.chain() == SpecularChain::None);
    refract_out(t, kA);
    CHECK(t.chain() == SpecularChain::Refraction);
    CHECK(t.exit() == kA);
    const ChainTracker mirrored = t.glint(kB);
    CHECK(mirrored.chain() == SpecularChain::RefractionReflection);
    CHECK(mirrored.reflection() == kB);
    CHECK(mirrored.exit() == kA);

    t.scattered();
    reflect_inside(t, kB);
    CHECK_FALSE(t.chain());  // still inside: nothing meets the light yet
    refract_out(t, kC);
    CHECK(t.chain() == SpecularChain::ReflectionRefraction);
    CHECK(t.reflection() == kB);
    CHECK(t.exit() == kC);
}

TEST_CASE("specular chains: longer chains belong to no estimator", "[specular_chain]") {
    ChainTracker t;
    SECTION("two reflections inside") {
        t.scattered();
        reflect_inside(t, kA);
        reflect_inside(t, kB);
        refract_out(t, kC);
        CHECK_FALSE(t.chain());
    }
    SECTION("out of one part and into another") {
        t.scattered();
        refract_out(t, kA);
        refract_in(t, kB);
        refract_out(t, kC);
        CHECK_FALSE(t.chain());
    }
    SECTION("a glint after an internal reflection and the refraction out") {
        // The second-chain estimator follows the refraction straight to the
        // light; a path mirrored off another part after that chain is not
        // one it makes, and must keep its full weight.
        t.scattered();
        reflect_inside(t, kA);
        refract_out(t, kB);
        REQUIRE(t.chain() == SpecularChain::ReflectionRefraction);
        CHECK_FALSE(t.glint(kC).chain());
    }
    SECTION("a scattering starts a new chain") {
        t.scattered();
        reflect_inside(t, kA);
        reflect_inside(t, kB);
        t.scattered();
        refract_out(t, kC);
        CHECK(t.chain() == SpecularChain::Refraction);
    }
}
