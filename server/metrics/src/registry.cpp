#include "penumbra/metrics/registry.hpp"

#include <penumbra/base/assert.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace penumbra::metrics {
namespace {

std::string number(double v) {
    if (std::isinf(v)) {
        return v > 0 ? "+Inf" : "-Inf";
    }
    char text[64];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

}  // namespace

Histogram::Histogram(std::vector<double> upper_bounds)
    : bounds_(std::move(upper_bounds))
    , counts_(bounds_.size() + 1, 0) {
    PENUMBRA_ASSERT(std::is_sorted(bounds_.begin(), bounds_.end()), "bucket bounds must be sorted");
}

void Histogram::observe(double v) {
    const std::lock_guard lock(mutex_);
    const auto bucket = static_cast<std::size_t>(
            std::lower_bound(bounds_.begin(), bounds_.end(), v) - bounds_.begin());
    ++counts_[bucket];
    sum_ += v;
    ++count_;
}

Histogram::Snapshot Histogram::snapshot() const {
    const std::lock_guard lock(mutex_);
    Snapshot s;
    s.upper_bounds = bounds_;
    std::uint64_t running = 0;
    for (const auto c : counts_) {
        running += c;
        s.cumulative.push_back(running);
    }
    s.sum = sum_;
    s.count = count_;
    return s;
}

double Histogram::quantile(double q) const {
    const Snapshot s = snapshot();
    if (s.count == 0) {
        return 0.0;
    }
    const double rank = q * static_cast<double>(s.count);
    for (std::size_t i = 0; i < s.upper_bounds.size(); ++i) {
        if (static_cast<double>(s.cumulative[i]) >= rank) {
            return s.upper_bounds[i];
        }
    }
    return s.upper_bounds.empty() ? 0.0 : s.upper_bounds.back();
}

Counter& Registry::counter(const std::string& name, const std::string& help) {
    const std::lock_guard lock(mutex_);
    Entry& e = entries_[name];
    if (!e.counter) {
        PENUMBRA_ASSERT(!e.gauge && !e.histogram, "metric name reused with another kind");
        e.help = help;
        e.counter = std::make_unique<Counter>();
    }
    return *e.counter;
}

Gauge& Registry::gauge(const std::string& name, const std::string& help) {
    const std::lock_guard lock(mutex_);
    Entry& e = entries_[name];
    if (!e.gauge) {
        PENUMBRA_ASSERT(!e.counter && !e.histogram, "metric name reused with another kind");
        e.help = help;
        e.gauge = std::make_unique<Gauge>();
    }
    return *e.gauge;
}

Histogram& Registry::histogram(const std::string& name, const std::string& help,
                               std::vector<double> upper_bounds) {
    const std::lock_guard lock(mutex_);
    Entry& e = entries_[name];
    if (!e.histogram) {
        PENUMBRA_ASSERT(!e.counter && !e.gauge, "metric name reused with another kind");
        e.help = help;
        e.histogram = std::make_unique<Histogram>(std::move(upper_bounds));
    }
    return *e.histogram;
}

std::string Registry::prometheus_text() const {
    const std::lock_guard lock(mutex_);
    std::string out;
    for (const auto& [name, e] : entries_) {
        out += "# HELP " + name + " " + e.help + "\n";
        if (e.counter) {
            out += "# TYPE " + name + " counter\n" + name + " " +
                   std::to_string(e.counter->value()) + "\n";
        } else if (e.gauge) {
            out += "# TYPE " + name + " gauge\n" + name + " " + number(e.gauge->value()) + "\n";
        } else if (e.histogram) {
            const Histogram::Snapshot s = e.histogram->snapshot();
            out += "# TYPE " + name + " histogram\n";
            for (std::size_t i = 0; i < s.upper_bounds.size(); ++i) {
                out += name + "_bucket{le=\"" + number(s.upper_bounds[i]) + "\"} " +
                       std::to_string(s.cumulative[i]) + "\n";
            }
            out += name + "_bucket{le=\"+Inf\"} " + std::to_string(s.cumulative.back()) + "\n";
            out += name + "_sum " + number(s.sum) + "\n";
            out += name + "_count " + std::to_string(s.count) + "\n";
        }
    }
    return out;
}

std::vector<double> latency_buckets_ms() {
    return {1, 2, 5, 10, 20, 35, 50, 75, 100, 150, 200, 300, 500, 750, 1000, 2000, 5000, 10000};
}

}  // namespace penumbra::metrics
