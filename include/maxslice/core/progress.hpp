#pragma once

#include <atomic>
#include <functional>
#include <string_view>

namespace maxslice::core {

/// Reports progress of a long stage and lets the caller cancel it. Callbacks may come from
/// any thread; a default-constructed Progress does nothing.
class Progress {
public:
    using Callback = std::function<void(std::string_view stage, double fraction)>;

    Progress() = default;
    explicit Progress(Callback callback) : callback_(std::move(callback)) {}

    /// fraction in [0, 1] of the named stage.
    void report(std::string_view stage, double fraction) const {
        if (callback_) callback_(stage, fraction);
    }
    void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
    [[nodiscard]] bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

private:
    Callback callback_;
    std::atomic<bool> cancelled_{false};
};

}  // namespace maxslice::core
