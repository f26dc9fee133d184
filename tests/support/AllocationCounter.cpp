// AllocationCounter: the replacement of every replaceable global operator new / delete
// ([new.delete]), counting each allocation. Blocks come from std::malloc and
// std::aligned_alloc and go back to std::free, which AddressSanitizer and ThreadSanitizer
// intercept, so the sanitizers still check every block.
//
// Exactly one translation unit of an executable may define these; CMake builds this file
// as the OBJECT library terrain_test_allocation_counter, so linking it puts this object
// (and so the replacement) into the test executable unconditionally.
#include "AllocationCounter.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>

namespace {

// Constant-initialised: allocations happen before main and on fresh threads, before any
// dynamic initialiser could run, and a thread_local without a dynamic initialiser needs no
// TLS wrapper call that could itself allocate.
constinit std::atomic<std::uint64_t> g_allThreads{0};
constinit thread_local std::uint64_t t_thisThread = 0;

void countOne() noexcept {
    g_allThreads.fetch_add(1, std::memory_order_relaxed);
    ++t_thisThread;
}

// [new.delete.single]/3: on failure call the new-handler and retry; without one, throw.
void waitForMemoryOrThrow() {
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
}

void* allocate(std::size_t size) {
    countOne();
    // operator new(0) must still return a unique pointer; malloc(0) may return null.
    const std::size_t bytes = size == 0 ? 1 : size;
    while (true) {
        if (void* block = std::malloc(bytes)) return block;
        waitForMemoryOrThrow();
    }
}

void* allocateAligned(std::size_t size, std::align_val_t alignment) {
    countOne();
    const std::size_t align = std::max(static_cast<std::size_t>(alignment), sizeof(void*));
    // aligned_alloc wants the size to be a multiple of the alignment (ASan reports it
    // otherwise); round up, and fail like an out-of-memory on overflow.
    if (size > std::numeric_limits<std::size_t>::max() - align) throw std::bad_alloc();
    const std::size_t bytes = size == 0 ? align : (size + align - 1) / align * align;
    while (true) {
        if (void* block = std::aligned_alloc(align, bytes)) return block;
        waitForMemoryOrThrow();
    }
}

}  // namespace

namespace terrain::test {

std::uint64_t allocationCountAllThreads() { return g_allThreads.load(std::memory_order_relaxed); }

std::uint64_t allocationCountThisThread() { return t_thisThread; }

}  // namespace terrain::test

// The nothrow forms behave as the throwing ones inside a try block ([new.delete.single]/7).

void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void* operator new(std::size_t size, std::align_val_t alignment) {
    return allocateAligned(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
    return allocateAligned(size, alignment);
}

void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return allocate(size);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return allocate(size);
    } catch (...) {
        return nullptr;
    }
}
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
    try {
        return allocateAligned(size, alignment);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
    try {
        return allocateAligned(size, alignment);
    } catch (...) {
        return nullptr;
    }
}

// Every block, aligned or not, came from malloc or aligned_alloc: std::free releases both.
void operator delete(void* block) noexcept { std::free(block); }
void operator delete[](void* block) noexcept { std::free(block); }
void operator delete(void* block, std::size_t) noexcept { std::free(block); }
void operator delete[](void* block, std::size_t) noexcept { std::free(block); }
void operator delete(void* block, std::align_val_t) noexcept { std::free(block); }
void operator delete[](void* block, std::align_val_t) noexcept { std::free(block); }
void operator delete(void* block, std::size_t, std::align_val_t) noexcept { std::free(block); }
void operator delete[](void* block, std::size_t, std::align_val_t) noexcept { std::free(block); }
void operator delete(void* block, const std::nothrow_t&) noexcept { std::free(block); }
void operator delete[](void* block, const std::nothrow_t&) noexcept { std::free(block); }
void operator delete(void* block, std::align_val_t, const std::nothrow_t&) noexcept {
    std::free(block);
}
void operator delete[](void* block, std::align_val_t, const std::nothrow_t&) noexcept {
    std::free(block);
}
