#pragma once

// Memory the server keeps for reuse (volumes in RAM, their textures, light buffers, stills on the
// GPU) under a byte budget, the least recently used given up first.

#include <algorithm>
#include <cstddef>
#include <functional>
#include <list>
#include <utility>

namespace penumbra::base {

// Entries known by what their content depends on, each with its size in bytes, most recently used
// first. Making room for an entry evicts the least recently used ones until it fits the budget. An
// entry larger than the whole budget is still taken, once everything that may go has gone:
// refusing one is its owner's decision, made before it spends the work of building it. Keys are
// compared with ==; a cache holds a handful of large entries, so lookups walk the list.
template <class Key, class Value>
class LruCache {
public:
    struct Entry {
        Key key;
        Value value;
        std::size_t bytes = 0;
    };

    struct Hooks {
        // An entry for which this is true is never evicted (the volume being drawn).
        std::function<bool(const Entry&)> must_stay = {};
        // Called with each evicted entry before it is dropped, for what goes with it.
        std::function<void(Entry&)> on_evict = {};
    };

    explicit LruCache(std::size_t budget, Hooks hooks = {})
        : budget_(budget)
        , hooks_(std::move(hooks)) {}

    LruCache(const LruCache&) = delete;
    LruCache& operator=(const LruCache&) = delete;

    // The value of `key`'s entry, which becomes the most recently used; null when none has it.
    Value* find(const Key& key) {
        const auto it = locate(key);
        if (it == entries_.end()) {
            return nullptr;
        }
        entries_.splice(entries_.begin(), entries_, it);
        return &entries_.front().value;
    }

    // The value of `key`'s entry, its place unchanged; null when none has it.
    [[nodiscard]] const Value* peek(const Key& key) const {
        const auto it = locate(key);
        return it == entries_.end() ? nullptr : &it->value;
    }

    // Evicts least recently used entries until `incoming` more bytes fit the budget.
    void make_room(std::size_t incoming) { evict_until_fits(incoming, entries_.end()); }

    // Adds an entry as the most recently used, in place of the entry `key` had, after making room
    // for it.
    Value& insert(Key key, Value value, std::size_t bytes) {
        if (const auto old = locate(key); old != entries_.end()) {
            bytes_ -= old->bytes;
            entries_.erase(old);
        }
        make_room(bytes);
        entries_.push_front({std::move(key), std::move(value), bytes});
        bytes_ += bytes;
        return entries_.front().value;
    }

    // Sets the size of `key`'s entry (grown by something built for it later) and evicts others
    // until the total fits again; the entry itself stays, since its owner is using it.
    void resize(const Key& key, std::size_t bytes) {
        const auto it = locate(key);
        if (it == entries_.end()) {
            return;
        }
        bytes_ = bytes_ - it->bytes + bytes;
        it->bytes = bytes;
        evict_until_fits(0, it);
    }

    // Removes every entry `remove` is true of. This is no eviction: on_evict is not called.
    template <class Predicate>
    std::size_t remove_if(Predicate remove) {
        std::size_t removed = 0;
        for (auto it = entries_.begin(); it != entries_.end();) {
            if (remove(std::as_const(*it))) {
                bytes_ -= it->bytes;
                it = entries_.erase(it);
                ++removed;
            } else {
                ++it;
            }
        }
        return removed;
    }

    [[nodiscard]] std::size_t bytes() const { return bytes_; }

    [[nodiscard]] std::size_t budget() const { return budget_; }

    [[nodiscard]] std::size_t size() const { return entries_.size(); }

    // The entries, most recently used first.
    [[nodiscard]] auto begin() const { return entries_.cbegin(); }

    [[nodiscard]] auto end() const { return entries_.cend(); }

private:
    using Iterator = typename std::list<Entry>::iterator;

    [[nodiscard]] Iterator locate(const Key& key) { return locate_in(entries_, key); }

    [[nodiscard]] auto locate(const Key& key) const { return locate_in(entries_, key); }

    template <class Entries>
    static auto locate_in(Entries& entries, const Key& key) {
        return std::find_if(entries.begin(), entries.end(),
                            [&](const Entry& entry) { return entry.key == key; });
    }

    // Evicts from the least recently used end, passing over `keep` and the entries that must
    // stay, until `incoming` more bytes fit or nothing more may go.
    void evict_until_fits(std::size_t incoming, Iterator keep) {
        auto it = entries_.end();
        while (it != entries_.begin() && bytes_ + incoming > budget_) {
            --it;
            if (it == keep || (hooks_.must_stay && hooks_.must_stay(*it))) {
                continue;
            }
            if (hooks_.on_evict) {
                hooks_.on_evict(*it);
            }
            bytes_ -= it->bytes;
            it = entries_.erase(it);
        }
    }

    std::list<Entry> entries_;
    std::size_t bytes_ = 0;
    std::size_t budget_;
    Hooks hooks_;
};

}  // namespace penumbra::base
