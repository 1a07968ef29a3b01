// The byte-budgeted cache behind the renderer's textures, light buffers and stills and the
// volume store's loaded volumes.

#include <penumbra/base/lru_cache.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace penumbra::base {
namespace {

using Cache = LruCache<std::string, int>;

// The keys, most recently used first.
std::vector<std::string> keys(const Cache& cache) {
    std::vector<std::string> out;
    for (const auto& entry : cache) {
        out.push_back(entry.key);
    }
    return out;
}

TEST(LruCache, EvictsTheLeastRecentlyUsedUntilAnEntryFits) {
    Cache cache(100);
    cache.insert("a", 1, 40);
    cache.insert("b", 2, 40);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"b", "a"}));
    ASSERT_NE(cache.find("a"), nullptr);  // a is now the most recently used
    EXPECT_EQ(*cache.find("a"), 1);
    cache.insert("c", 3, 30);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"c", "a"}));
    EXPECT_EQ(cache.bytes(), 70u);
    EXPECT_EQ(cache.find("b"), nullptr);
    cache.insert("d", 4, 100);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"d"}));
    EXPECT_EQ(cache.bytes(), 100u);
}

TEST(LruCache, PeekLeavesTheOrderAsItWas) {
    Cache cache(100);
    cache.insert("a", 1, 10);
    cache.insert("b", 2, 10);
    ASSERT_NE(cache.peek("a"), nullptr);
    EXPECT_EQ(*cache.peek("a"), 1);
    EXPECT_EQ(cache.peek("z"), nullptr);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"b", "a"}));
}

TEST(LruCache, MakingRoomEvictsWithoutInserting) {
    Cache cache(100);
    cache.insert("a", 1, 50);
    cache.insert("b", 2, 30);
    cache.make_room(20);
    EXPECT_EQ(cache.size(), 2u);
    cache.make_room(40);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"b"}));
    EXPECT_EQ(cache.bytes(), 30u);
}

TEST(LruCache, AnEntryLargerThanTheBudgetIsKeptAloneAndGoesFirstNextTime) {
    Cache cache(100);
    cache.insert("a", 1, 10);
    cache.insert("huge", 2, 250);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"huge"}));
    EXPECT_EQ(cache.bytes(), 250u);
    cache.insert("b", 3, 10);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"b"}));
}

TEST(LruCache, EntriesThatMustStayAreNeverEvicted) {
    std::string pinned = "a";
    Cache cache(100, {.must_stay = [&](const Cache::Entry& entry) { return entry.key == pinned; }});
    cache.insert("a", 1, 60);
    cache.insert("b", 2, 30);
    cache.insert("c", 3, 30);  // a is the oldest but stays: b goes
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"c", "a"}));
    cache.insert("d", 4, 80);  // everything that may go goes, and the total is over the budget
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"d", "a"}));
    EXPECT_EQ(cache.bytes(), 140u);
    pinned = "d";
    cache.insert("e", 5, 10);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"e", "d"}));
}

TEST(LruCache, EvictedEntriesReachTheHookAndRemovedOnesDoNot) {
    std::vector<std::string> evicted;
    Cache cache(100, {.on_evict = [&](Cache::Entry& entry) { evicted.push_back(entry.key); }});
    cache.insert("a", 1, 40);
    cache.insert("b", 2, 40);
    cache.insert("c", 3, 40);
    cache.insert("d", 4, 40);
    EXPECT_EQ(evicted, (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(cache.remove_if([](const Cache::Entry& entry) { return entry.value == 3; }), 1u);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"d"}));
    EXPECT_EQ(cache.bytes(), 40u);
    EXPECT_EQ(evicted.size(), 2u);
}

TEST(LruCache, InsertingAKeyAgainReplacesItsEntry) {
    Cache cache(100);
    cache.insert("a", 1, 60);
    cache.insert("b", 2, 20);
    cache.insert("a", 3, 70);  // the old a's bytes are given back before room is made
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(*cache.peek("a"), 3);
    EXPECT_EQ(cache.bytes(), 90u);
}

TEST(LruCache, AGrownEntryStaysAndPushesOthersOut) {
    Cache cache(100);
    cache.insert("a", 1, 30);
    cache.insert("b", 2, 30);
    cache.insert("c", 3, 30);
    cache.find("a");
    cache.resize("b", 60);  // b is not the most recently used, yet it stays
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(cache.bytes(), 90u);
    cache.resize("b", 200);
    EXPECT_EQ(keys(cache), (std::vector<std::string>{"b"}));
    EXPECT_EQ(cache.bytes(), 200u);
}

}  // namespace
}  // namespace penumbra::base
