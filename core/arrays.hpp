// Views and owning arrays for the compiled core.
//
// The algorithms work on small dense arrays: vectors of n <= ~20 entries and row-major
// matrices whose rows are points of a set (simplices, facets, witnesses). A view is a pointer
// and a shape, passed by value; an Array owns its entries. Nothing here allocates but Array
// (and a LocalBlock too large for its stack part).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace gf {

using Int = std::int64_t;

constexpr double INF = std::numeric_limits<double>::infinity();

// a float64 vector view
struct Vec {
    double* d = nullptr;
    Int n = 0;
    double& operator[](Int i) const { return d[i]; }
    // x[:k]
    Vec head(Int k) const { return {d, k}; }
    // x[a:a + k]
    Vec segment(Int a, Int k) const { return {d + a, k}; }
    // x[a:]
    Vec tail_from(Int a) const { return {d + a, n - a}; }
};

// an int64 vector view (programs, pivots)
struct IVec {
    Int* d = nullptr;
    Int n = 0;
    Int& operator[](Int i) const { return d[i]; }
    IVec head(Int k) const { return {d, k}; }
};

// a row-major float64 matrix view: rows of `cols` entries, `ld` apart
struct Mat {
    double* d = nullptr;
    Int rows = 0;
    Int cols = 0;
    Int ld = 0;
    double& operator()(Int i, Int j) const { return d[i * ld + j]; }
    // M[i]
    Vec row(Int i) const { return {d + i * ld, cols}; }
    // M[:k]
    Mat top(Int k) const { return {d, k, cols, ld}; }
    // M[a:b]
    Mat rows_range(Int a, Int b) const { return {d + a * ld, b - a, cols, ld}; }
    // M[a:]
    Mat rows_from(Int a) const { return {d + a * ld, rows - a, cols, ld}; }
    // M[:, :c] (the same rows, their first c entries)
    Mat left(Int c) const { return {d, rows, c, ld}; }
};

// a contiguous matrix view laid over a vector's entries from `start`: numba's
// view(buf, start, (rows, cols))
inline Mat mat_view(Vec buf, Int start, Int rows, Int cols) {
    return {buf.d + start, rows, cols, cols};
}

// std::allocator, but a vector of n entries is left uninitialized unless a value is given: the
// large work arrays (IE's pool of support points, max_iter + n + 1 rows) are written before they
// are read, and zeroing them cost more than the shot
template <class T>
struct DefaultInit : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = DefaultInit<U>;
    };
    using std::allocator<T>::allocator;
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... A>
    void construct(U* p, A&&... a) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
    }
};

// an owning float64 array of one or two dimensions, zero-initialized (`uninitialized` leaves
// its entries for the caller to write before reading)
struct Array {
    std::vector<double, DefaultInit<double>> data;
    Int rows = 0;   // a vector's length, or a matrix's rows
    Int cols = 0;   // a matrix's columns (0 for a vector)
    int ndim = 1;
    Array() = default;
    explicit Array(Int n) : data(static_cast<size_t>(n), 0.0), rows(n), cols(0), ndim(1) {}
    Array(Int r, Int c) : data(static_cast<size_t>(r * c), 0.0), rows(r), cols(c), ndim(2) {}
    static Array uninitialized(Int r, Int c) {
        Array a;
        a.data = std::vector<double, DefaultInit<double>>(static_cast<size_t>(r * c));
        a.rows = r;
        a.cols = c;
        a.ndim = 2;
        return a;
    }
    Vec vec() { return {data.data(), static_cast<Int>(data.size())}; }
    Mat mat() { return {data.data(), rows, cols, cols}; }
    Int size() const { return static_cast<Int>(data.size()); }
};

// an owning int64 array, zero-initialized (`uninitialized`: as Array's)
struct IArray {
    std::vector<Int, DefaultInit<Int>> data;
    IArray() = default;
    explicit IArray(Int n) : data(static_cast<size_t>(n), 0) {}
    static IArray uninitialized(Int n) {
        IArray a;
        a.data = std::vector<Int, DefaultInit<Int>>(static_cast<size_t>(n));
        return a;
    }
    IVec vec() { return {data.data(), static_cast<Int>(data.size())}; }
};

// `size` entries of work space, the first `zeroed` of them zero: in the object itself up to
// LOCAL entries (a shot's work arrays on a grasp's sets, made at every call, on the caller's
// stack), else on the heap, all zeroed. Views of it point into it: not copied.
template <class T, Int LOCAL>
struct LocalBlock {
    T local[LOCAL];
    std::vector<T> heap;
    T* data;
    LocalBlock(Int size, Int zeroed) {
        if (size <= LOCAL) {
            std::fill_n(local, zeroed, T{});
            data = local;
        } else {
            heap.assign(static_cast<size_t>(size), T{});
            data = heap.data();
        }
    }
    LocalBlock(const LocalBlock&) = delete;
    LocalBlock& operator=(const LocalBlock&) = delete;
};

}  // namespace gf
