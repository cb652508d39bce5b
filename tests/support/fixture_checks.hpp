#pragma once
// Small helpers shared by the fixture builders in tests/support.

#include <stdexcept>

#include "support/fixtures.hpp"

namespace maxslice::test::detail {

/// Throws std::invalid_argument(what) unless condition: a fixture with impossible
/// parameters is a bug in the test that asks for it.
inline void require(bool condition, const char* what) {
    if (!condition) throw std::invalid_argument(what);
}

/// Twice the signed area of triangle (o, a, b): positive when counter-clockwise.
inline double cross2(CapPoint o, CapPoint a, CapPoint b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

}  // namespace maxslice::test::detail
