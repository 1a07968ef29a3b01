#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace penumbra::metrics {

// A monotonically increasing count.
class Counter {
public:
    void add(std::uint64_t n = 1) { value_.fetch_add(n, std::memory_order_relaxed); }

    [[nodiscard]] std::uint64_t value() const { return value_.load(std::memory_order_relaxed); }

private:
    std::atomic<std::uint64_t> value_{0};
};

// A value that goes up and down.
class Gauge {
public:
    void set(double v) { value_.store(v, std::memory_order_relaxed); }

    void add(double d) {
        double old = value_.load(std::memory_order_relaxed);
        while (!value_.compare_exchange_weak(old, old + d, std::memory_order_relaxed)) {
        }
    }

    [[nodiscard]] double value() const { return value_.load(std::memory_order_relaxed); }

private:
    std::atomic<double> value_{0.0};
};

// Observations counted into cumulative buckets (Prometheus semantics), plus sum and count.
class Histogram {
public:
    explicit Histogram(std::vector<double> upper_bounds);

    void observe(double v);

    struct Snapshot {
        std::vector<double> upper_bounds;
        std::vector<std::uint64_t> cumulative;  // per bound, then +Inf last
        double sum = 0.0;
        std::uint64_t count = 0;
    };

    [[nodiscard]] Snapshot snapshot() const;

    // The q-quantile (0..1) estimated from the buckets (the upper bound of the bucket it falls in).
    [[nodiscard]] double quantile(double q) const;

private:
    mutable std::mutex mutex_;
    std::vector<double> bounds_;
    std::vector<std::uint64_t> counts_;  // per bucket (not cumulative), +Inf last
    double sum_ = 0.0;
    std::uint64_t count_ = 0;
};

// Named metrics of one process, written in the Prometheus text exposition format. Metrics are
// created once and live as long as the registry; lookups hand out stable references.
class Registry {
public:
    Counter& counter(const std::string& name, const std::string& help);
    Gauge& gauge(const std::string& name, const std::string& help);
    Histogram& histogram(const std::string& name, const std::string& help,
                         std::vector<double> upper_bounds);

    [[nodiscard]] std::string prometheus_text() const;

private:
    struct Entry {
        std::string help;
        std::unique_ptr<Counter> counter;
        std::unique_ptr<Gauge> gauge;
        std::unique_ptr<Histogram> histogram;
    };

    mutable std::mutex mutex_;
    std::map<std::string, Entry> entries_;
};

// Buckets for latencies in milliseconds, 1 ms to 10 s.
std::vector<double> latency_buckets_ms();

}  // namespace penumbra::metrics
