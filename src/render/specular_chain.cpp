#include "jade/render/specular_chain.h"

namespace jade {

// Each class is one exact sequence from a scattering: any other event (a
// second reflection inside, out of one part and into another) makes the
// chain Other until the next scattering.
void ChainTracker::record(const glm::vec3& p, bool entering, bool reflected, bool inside_after) {
    const bool refracted_out = !entering && !reflected;
    if (state_ == State::Straight && !entering && reflected && inside_after) {
        state_ = State::Reflected;
        reflection_ = p;
    } else if (state_ == State::Straight && refracted_out) {
        state_ = State::Refracted;
        exit_ = p;
    } else if (state_ == State::Reflected && refracted_out) {
        state_ = State::ReflectedRefracted;
        exit_ = p;
    } else {
        state_ = State::Other;
    }
}

ChainTracker ChainTracker::glint(const glm::vec3& p) const {
    ChainTracker g = *this;
    g.state_ = state_ == State::Refracted ? State::RefractedReflected : State::Other;
    g.reflection_ = p;
    return g;
}

std::optional<SpecularChain> ChainTracker::chain() const {
    switch (state_) {
    case State::Straight: return SpecularChain::None;
    case State::Refracted: return SpecularChain::Refraction;
    case State::ReflectedRefracted: return SpecularChain::ReflectionRefraction;
    case State::RefractedReflected: return SpecularChain::RefractionReflection;
    case State::Other:
    case State::Reflected: break;
    }
    return std::nullopt;
}

}  // namespace jade
