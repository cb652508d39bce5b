#include "maxslice/machine/speed_law.hpp"

#include <algorithm>

namespace maxslice::machine {

SpeedLaw SpeedLaw::of(const ProcessProfile& process) {
    SpeedLaw law;
    if (process.speed_height.size() >= 2) {
        law.points_ = process.speed_height;
        law.feed_min_ = law.points_.front().feed_mm_min;
        law.feed_max_ = law.points_.back().feed_mm_min;
        return law;
    }
    law.mass_ = process.layer_height_mm * process.deposition_feed_mm_min;
    law.feed_min_ = law.mass_ / process.h_max_mm;
    law.feed_max_ = law.mass_ / process.h_min_mm;
    return law;
}

double SpeedLaw::height_mm(double feed_mm_min) const {
    const double f = std::clamp(feed_mm_min, feed_min_, feed_max_);
    if (points_.empty()) return mass_ / f;
    // The segment whose feed range holds f (feeds strictly increase: validated).
    const auto hi =
        std::upper_bound(points_.begin() + 1, points_.end() - 1, f,
                         [](double v, const SpeedPoint& p) { return v < p.feed_mm_min; });
    const SpeedPoint& b = *hi;
    const SpeedPoint& a = *(hi - 1);
    const double t = (f - a.feed_mm_min) / (b.feed_mm_min - a.feed_mm_min);
    return a.height_mm + t * (b.height_mm - a.height_mm);
}

double SpeedLaw::feed_mm_min(double height_mm) const {
    if (points_.empty()) return std::clamp(mass_ / height_mm, feed_min_, feed_max_);
    // Heights strictly decrease with the feed.
    if (height_mm >= points_.front().height_mm) return feed_min_;
    if (height_mm <= points_.back().height_mm) return feed_max_;
    const auto hi = std::find_if(points_.begin() + 1, points_.end(),
                                 [&](const SpeedPoint& p) { return p.height_mm <= height_mm; });
    const SpeedPoint& b = *hi;
    const SpeedPoint& a = *(hi - 1);
    const double t = (a.height_mm - height_mm) / (a.height_mm - b.height_mm);
    return a.feed_mm_min + t * (b.feed_mm_min - a.feed_mm_min);
}

}  // namespace maxslice::machine
