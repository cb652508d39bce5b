#pragma once
// Direct 3D layers (METHOD.md section 10): a single track gets lower as the scanning speed
// rises. The law maps a deposit feed to the height of the track it lays and back.

#include <vector>

#include "maxslice/machine/profile.hpp"

namespace maxslice::machine {

/// The process's speed law, monotone: a higher feed lays a lower track.
/// - Measured (`process.speed_height` given): piecewise linear between the pairs; the window
///   is the measured feed range, and outside it the law holds the end values.
/// - Otherwise the constant-mass law through the nominal point: at a fixed powder feed the
///   metal laid per mm falls as 1 / feed, so height x feed = layer_height_mm x
///   deposition_feed_mm_min; the window is the feeds that lay [h_min_mm, h_max_mm].
/// docs/profiles.md ("Speed law") and docs/decisions/0011-speed-law.md.
class SpeedLaw {
public:
    /// The law of a validated process profile.
    [[nodiscard]] static SpeedLaw of(const ProcessProfile& process);

    [[nodiscard]] bool measured() const { return !points_.empty(); }
    /// The feed window, mm/min.
    [[nodiscard]] double feed_min_mm_min() const { return feed_min_; }
    [[nodiscard]] double feed_max_mm_min() const { return feed_max_; }
    /// The heights the window can lay: height at feed_max and at feed_min, mm.
    [[nodiscard]] double height_min_mm() const { return height_mm(feed_max_); }
    [[nodiscard]] double height_max_mm() const { return height_mm(feed_min_); }

    /// The track height a feed lays (the feed clamped to the window), mm.
    [[nodiscard]] double height_mm(double feed_mm_min) const;
    /// The feed that lays `height_mm`, clamped to the window (mm/min); the clamp shows as
    /// height_mm(result) != the height asked for.
    [[nodiscard]] double feed_mm_min(double height_mm) const;

private:
    std::vector<SpeedPoint> points_;  // measured, feeds increasing; empty = constant mass
    double mass_ = 0.0;               // height x feed of the constant-mass law
    double feed_min_ = 0.0;
    double feed_max_ = 0.0;
};

}  // namespace maxslice::machine
