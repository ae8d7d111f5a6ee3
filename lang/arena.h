// A bump allocator for the syntax tree: nodes, their child arrays and their names are carved out
// of large chunks and freed together when the tree is dropped, so a tree of a million nodes costs
// one free per chunk and no recursion. Objects that own memory themselves (a packed list's shared
// numbers) are destroyed by the arena, in reverse order of creation; all others must be trivially
// destructible, which `make` checks at compile time.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <span>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace wsd::lang {

class Arena {
public:
    Arena() = default;
    Arena(const Arena&) = delete;
    Arena& operator=(const Arena&) = delete;
    ~Arena() {
        for (auto it = finalizers_.rbegin(); it != finalizers_.rend(); ++it) it->destroy(it->object);
    }

    // A new T built from args; it lives as long as the arena.
    template <class T, class... Args>
    T* make(Args&&... args) {
        static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
        T* p = new (allocate(sizeof(T), alignof(T))) T(std::forward<Args>(args)...);
        if constexpr (!std::is_trivially_destructible_v<T>)
            finalizers_.push_back({p, [](void* o) { static_cast<T*>(o)->~T(); }});
        return p;
    }

    // A copy of `items` in the arena (trivially copyable elements only).
    template <class T>
    std::span<T> copy(const std::vector<T>& items) {
        static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
        if (items.empty()) return {};
        T* p = static_cast<T*>(allocate(sizeof(T) * items.size(), alignof(T)));
        std::memcpy(static_cast<void*>(p), items.data(), sizeof(T) * items.size());
        return {p, items.size()};
    }

    std::string_view copy(std::string_view text) {
        if (text.empty()) return {};
        char* p = static_cast<char*>(allocate(text.size(), 1));
        std::memcpy(p, text.data(), text.size());
        return {p, text.size()};
    }

private:
    static constexpr size_t kChunk = size_t(64) << 10;

    // Chunks come from operator new[], aligned for every node type (checked in make).
    void* allocate(size_t size, size_t align) {
        size_t at = (used_ + align - 1) & ~(align - 1);
        if (at + size <= capacity_) {
            used_ = at + size;
            return chunks_.back().get() + at;
        }
        if (size > kChunk / 4) {
            // A large array gets a chunk of its own, kept behind the current one so that the
            // current one stays open for small nodes.
            auto big = std::make_unique<std::byte[]>(size);
            std::byte* p = big.get();
            chunks_.insert(chunks_.empty() ? chunks_.end() : chunks_.end() - 1, std::move(big));
            return p;
        }
        chunks_.push_back(std::make_unique<std::byte[]>(kChunk));
        capacity_ = kChunk;
        used_ = size;
        return chunks_.back().get();
    }

    struct Finalizer {
        void* object;
        void (*destroy)(void*);
    };
    std::vector<std::unique_ptr<std::byte[]>> chunks_;
    std::vector<Finalizer> finalizers_;
    size_t used_ = 0, capacity_ = 0;
};

}  // namespace wsd::lang
