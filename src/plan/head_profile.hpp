// The head's outline in its (t, r) half plane, with the trigonometry done once: the exact
// distances behind plan/nozzle.hpp and the bounds the build order prunes with. Private to plan.
#pragma once

#include <array>

#include "maxslice/plan/nozzle.hpp"

namespace maxslice::plan::detail {

class HeadProfile {
public:
    explicit HeadProfile(const Nozzle& nozzle);

    /// Signed distance to the whole head (stream, nozzle cone, body); negative inside.
    [[nodiscard]] double distance(double t, double r) const;
    /// Distance to the hardware (the cone above the standoff, the body).
    [[nodiscard]] double hardware_distance(double t, double r) const;
    /// Distance to the powder stream (the cone up to the standoff).
    [[nodiscard]] double stream_distance(double t, double r) const;
    /// min(hardware_distance - cover, stream_distance + clearance): with `cover` the radius
    /// within which every point of the material lies from a sample, a lower bound at a sample
    /// of the hardware's gap to the material around it. *in_stream (when given) says whether
    /// the stream gave it.
    [[nodiscard]] double margin(double t, double r, double cover = 0.0,
                                bool* in_stream = nullptr) const;
    /// A lower bound of distance() over t in [t_lo, t_hi] and r >= r_lo.
    [[nodiscard]] double bound(double t_lo, double t_hi, double r_lo) const;
    /// A radius beyond which bound(t, t, r) >= m: a closer footprint point matters only
    /// within it (0 when nothing at height t can come within m).
    [[nodiscard]] double reach_within(double t, double m) const;
    /// The head's length along its axis (cone, plus the body when it has one), mm.
    [[nodiscard]] double length() const { return length_; }

private:
    // A convex quadrilateral of the half plane, counter-clockwise (t right, r up), its first
    // edge on the axis (r = 0: not a boundary of the solid of revolution); a triangle repeats
    // its last corner.
    struct Piece {
        std::array<double, 4> t{};
        std::array<double, 4> r{};
        bool present = false;
        std::array<double, 4> len{};  // edge i's length, from corner i to i + 1 (set by make)
    };
    static Piece make(std::array<double, 4> t, std::array<double, 4> r, bool present);
    static double piece_distance(const Piece& p, double t, double r);

    Nozzle nozzle_;
    double cos_half_ = 1.0;
    double sin_half_ = 0.0;
    double length_ = 0.0;
    bool body_ = false;
    Piece stream_, cone_, body_piece_;
    Piece whole_cone_;  // stream and nozzle: depths inside are the whole cone's
};

}  // namespace maxslice::plan::detail
