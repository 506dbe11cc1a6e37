/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

// zwidth._core: the C core (double precision) on numpy arrays.
//
// Every kernel takes float64 arrays, broadcasts them like a numpy ufunc (stride 0 along
// broadcast axes, no copies), and runs the element loop in C++ without the GIL for large
// arrays.  It returns a dict of output arrays, an int8 array "status" holding the zw_status
// of each element, and "errors", the number of elements whose status is not ZW_OK.  Where
// status is not ZW_OK the other outputs of that element are left unwritten: the Python
// layer (zwidth/_kernels.py) raises or masks them, so no invalid element ever carries a
// number.  No formula lives here: each element is one call of the C core.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

extern "C" {
#include "box_cert_glue.h"
#include "zwidth/device_loop.h"
#include "zwidth/loop.h"
#include "zwidth/loop_limits.h"
#include "zwidth/zwidth.h"
}

namespace py = pybind11;
using ssize = py::ssize_t;
using f64array = py::array_t<double, py::array::forcecast>;

namespace {

// Below this many elements releasing and re-taking the GIL costs more than it frees.
constexpr ssize kReleaseGilFrom = 4096;
// Work is handed out in chunks of this many elements; arrays this large use every core.
constexpr ssize kChunk = 16384;
constexpr ssize kThreadsFrom = 65536;
constexpr ssize kMaxThreads = 8;

ssize hardware_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return std::max<ssize>(1, std::min<ssize>(kMaxThreads, n));
}

// N float64 inputs broadcast against each other.
template <std::size_t N>
class Broadcast {
  public:
    explicit Broadcast(const std::array<f64array, N> &inputs) : inputs_(inputs) {
        std::size_t nd = 0;
        for (const auto &a : inputs_) nd = std::max(nd, static_cast<std::size_t>(a.ndim()));
        shape_.assign(nd, 1);
        for (std::size_t k = 0; k < N; ++k) {
            const auto &a = inputs_[k];
            const std::size_t offset = nd - static_cast<std::size_t>(a.ndim());
            for (std::size_t d = 0; d < static_cast<std::size_t>(a.ndim()); ++d) {
                const ssize n = a.shape(static_cast<ssize>(d));
                ssize &s = shape_[offset + d];
                if (n == s || n == 1) continue;
                if (s != 1) throw py::value_error("operands could not be broadcast together with shapes " +
                                                  shapes_text());
                s = n;
            }
        }
        size_ = 1;
        for (ssize s : shape_) size_ *= s;
        for (std::size_t k = 0; k < N; ++k) {
            const auto &a = inputs_[k];
            const std::size_t offset = nd - static_cast<std::size_t>(a.ndim());
            strides_[k].assign(nd, 0);
            for (std::size_t d = 0; d < static_cast<std::size_t>(a.ndim()); ++d)
                strides_[k][offset + d] = a.shape(static_cast<ssize>(d)) == 1 ? 0 : a.strides(static_cast<ssize>(d));
            base_[k] = reinterpret_cast<const char *>(a.data());
        }
    }

    ssize size() const { return size_; }

    // A C-contiguous output of the broadcast shape with `trailing` extra axes.
    template <class T>
    py::array_t<T> output(std::vector<ssize> trailing = {}) const {
        std::vector<ssize> shape(shape_);
        shape.insert(shape.end(), trailing.begin(), trailing.end());
        return py::array_t<T>(shape);
    }

    // A stretch of elements along the last axis: element j of input k is at
    // ptr[k] + j * stride[k] (bytes), and its flat output index is flat + j.
    struct Segment {
        ssize flat = 0, count = 0;
        std::array<const char *, N> ptr{};
        std::array<ssize, N> stride{};
    };

    // Runs the segments (rows split into chunks) on up to kMaxThreads threads, without the
    // GIL for large arrays.  make_worker() is called once per thread and returns a
    // callable ssize(const Segment &) giving the number of failed elements, so each thread
    // owns its caches.  Returns the total number of failed elements.
    template <class MakeWorker>
    ssize for_segments(MakeWorker &&make_worker) const {
        if (size_ == 0) return 0;
        const std::size_t nd = shape_.size();
        const ssize inner = nd == 0 ? 1 : shape_[nd - 1];
        const ssize rows = size_ / inner;
        const ssize per_row = (inner + kChunk - 1) / kChunk;
        const ssize segments = rows * per_row;
        std::atomic<ssize> next{0}, errors{0};
        auto work = [&] {
            auto worker = make_worker();
            ssize failed = 0;
            for (ssize s; (s = next.fetch_add(1)) < segments;) {
                Segment seg;
                const ssize row = s / per_row, j0 = (s % per_row) * kChunk;
                seg.flat = row * inner + j0;
                seg.count = std::min(kChunk, inner - j0);
                for (std::size_t k = 0; k < N; ++k) {
                    const char *p = base_[k];
                    ssize rest = row;
                    for (std::size_t d = nd >= 1 ? nd - 1 : 0; d-- > 0;) {
                        p += (rest % shape_[d]) * strides_[k][d];
                        rest /= shape_[d];
                    }
                    seg.stride[k] = nd == 0 ? 0 : strides_[k][nd - 1];
                    seg.ptr[k] = p + j0 * seg.stride[k];
                }
                failed += worker(seg);
            }
            errors += failed;
        };
        std::unique_ptr<py::gil_scoped_release> nogil;
        if (size_ >= kReleaseGilFrom) nogil.reset(new py::gil_scoped_release());
        const ssize threads = size_ >= kThreadsFrom ? std::min<ssize>(segments, hardware_threads()) : 1;
        std::vector<std::thread> pool;
        for (ssize t = 1; t < threads; ++t) pool.emplace_back(work);
        work();
        for (auto &t : pool) t.join();
        return errors.load();
    }

    // Calls fn(flat_index, x) for every element of seg, x[k] being input k there; fn
    // returns the element's zw_status, stored in status.  Returns the failed count.
    template <class Fn>
    static ssize each(const Segment &seg, int8_t *status, Fn &fn) {
        std::array<double, N> x;
        ssize failed = 0;
        for (ssize j = 0; j < seg.count; ++j) {
            for (std::size_t k = 0; k < N; ++k) std::memcpy(&x[k], seg.ptr[k] + j * seg.stride[k], sizeof(double));
            const zw_status st = fn(seg.flat + j, x);
            status[seg.flat + j] = static_cast<int8_t>(st);
            failed += st != ZW_OK;
        }
        return failed;
    }

    // Element-wise kernels: make_fn() returns, once per thread, a callable
    // zw_status(ssize flat, const std::array<double, N> &x).
    template <class MakeFn>
    ssize run(int8_t *status, MakeFn &&make_fn) const {
        return for_segments([&] {
            return [status, fn = make_fn()](const Segment &seg) mutable { return each(seg, status, fn); };
        });
    }

  private:
    std::string shapes_text() const {
        std::string out;
        for (const auto &a : inputs_) {
            out += out.empty() ? "(" : " (";
            for (ssize d = 0; d < a.ndim(); ++d) out += (d ? "," : "") + std::to_string(a.shape(d));
            out += a.ndim() == 1 ? ",)" : ")";
        }
        return out;
    }

    std::array<f64array, N> inputs_;
    std::vector<ssize> shape_;
    ssize size_ = 0;
    std::array<std::vector<ssize>, N> strides_;
    std::array<const char *, N> base_{};
};

double load(const char *p) {
    double x;
    std::memcpy(&x, p, sizeof x);
    return x;
}

const double *as_doubles(const char *p) { return reinterpret_cast<const double *>(p); }

// The segment's first `plant` inputs are constant along it (stride 0) and the others are
// aligned doubles at whole-element strides, as the batch functions of batch.h need.
template <class Segment>
bool one_plant(const Segment &seg, std::size_t plant) {
    for (std::size_t k = 0; k < seg.ptr.size(); ++k) {
        if (k < plant ? seg.stride[k] != 0
                      : seg.stride[k] % static_cast<ssize>(sizeof(double)) != 0 ||
                            reinterpret_cast<std::uintptr_t>(seg.ptr[k]) % alignof(double) != 0)
            return false;
    }
    return true;
}

// The plant (coefficients, or a device) made from an element's first Keys inputs, kept for
// the next element: a sweep over gains at one plant pays for the exponentials once.
template <class Plant, std::size_t Keys, zw_status (*init)(Plant *, const double *)>
class PlantCache {
  public:
    using plant_type = Plant;

    template <std::size_t N>
    zw_status get(const std::array<double, N> &x, const Plant **out) {
        static_assert(N >= Keys, "an element holds the plant's parameters first");
        if (!valid_ || std::memcmp(key_.data(), x.data(), sizeof key_) != 0) {  // bitwise: NaN too
            std::memcpy(key_.data(), x.data(), sizeof key_);
            status_ = init(&plant_, key_.data());
            valid_ = true;
        }
        *out = &plant_;
        return status_;
    }

  private:
    bool valid_ = false;
    std::array<double, Keys> key_{};
    zw_status status_ = ZW_OK;
    Plant plant_{};
};

zw_status init_coeffs(zw_coeffs *c, const double *key) { return zw_coeffs_init(c, key[0]); }
zw_status init_device(zw_device *d, const double *key) { return zw_device_init(d, key[0], key[1], key[2]); }
using CoeffsCache = PlantCache<zw_coeffs, 1, init_coeffs>;  // key: delta
using DeviceCache = PlantCache<zw_device, 3, init_device>;  // key: m, b, T

// Result of a kernel: {"outputs": {name: array}, "status": int8 array, "errors": int}.
class Result {
  public:
    template <std::size_t N>
    explicit Result(const Broadcast<N> &bc) : status_(bc.template output<int8_t>()) {}

    int8_t *status() { return status_.mutable_data(); }

    template <class T, std::size_t N>
    T *add(const Broadcast<N> &bc, const char *name, std::vector<ssize> trailing = {}) {
        auto a = bc.template output<T>(std::move(trailing));
        T *p = a.mutable_data();
        outputs_[name] = std::move(a);
        return p;
    }

    py::dict finish(ssize errors) {
        py::dict r;
        r["outputs"] = outputs_;
        r["status"] = status_;
        r["errors"] = errors;
        return r;
    }

  private:
    py::array_t<int8_t> status_;
    py::dict outputs_;
};

// Verdict outputs; `full` adds marginal, deciding and violated to "stable".
struct VerdictOut {
    VerdictOut(Result &r, const Broadcast<3> &bc3, bool full) { init(r, bc3, full); }
    VerdictOut(Result &r, const Broadcast<5> &bc5, bool full) { init(r, bc5, full); }

    void store(ssize i, const zw_verdict &v) const {
        stable[i] = v.stable;
        if (marginal) {
            marginal[i] = v.marginal;
            deciding[i] = static_cast<uint8_t>(v.deciding);
            violated[i] = static_cast<uint16_t>(v.violated);
        }
    }

    bool *stable = nullptr;
    bool *marginal = nullptr;
    uint8_t *deciding = nullptr;
    uint16_t *violated = nullptr;

  private:
    template <std::size_t N>
    void init(Result &r, const Broadcast<N> &bc, bool full) {
        stable = r.add<bool>(bc, "stable");
        if (!full) return;
        marginal = r.add<bool>(bc, "marginal");
        deciding = r.add<uint8_t>(bc, "deciding");
        violated = r.add<uint16_t>(bc, "violated");
    }
};

zw_region region_from(int region) {
    if (region < ZW_REGION_EXACT || region > ZW_REGION_SMALL) throw py::value_error("unknown region " + std::to_string(region));
    return static_cast<zw_region>(region);
}

// A kernel with one output of type T per element: call(plant, x, &out[i]) on the plant the
// Cache makes from the element's first inputs.
template <class T, class Cache, std::size_t N, class Call>
py::dict one_output(const std::array<f64array, N> &inputs, const char *name, Call call) {
    Broadcast<N> bc(inputs);
    Result r(bc);
    T *out = r.add<T>(bc, name);
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = Cache()](ssize i, const std::array<double, N> &x) mutable {
            const typename Cache::plant_type *p;
            const zw_status s = cache.get(x, &p);
            return s != ZW_OK ? s : call(p, x, &out[i]);
        };
    });
    return r.finish(errors);
}

// ---- normalized space: (delta, alpha, beta) -----------------------------------------

// The per-plant sweep: its AVX-512 (with fma) or AVX2 build (bindings/sweep_avx*.c, the same
// proved bounds) where the CPU has it, else the portable one.
#ifdef ZW_HAVE_SWEEP_SIMD
#define ZW_SWEEP_DECLARE(name)                                                                              \
    extern "C" zw_status name(size_t n, const double *delta, ptrdiff_t delta_stride, const double *alpha,  \
                              ptrdiff_t alpha_stride, const double *beta, ptrdiff_t beta_stride, bool *stable, \
                              size_t *first_invalid);
ZW_SWEEP_DECLARE(zw_sweep_check_many_avx2)
ZW_SWEEP_DECLARE(zw_sweep_check_many_avx512)
#undef ZW_SWEEP_DECLARE
#endif
using SweepCheck = decltype(&zw_sweep_check_many);
SweepCheck choose_sweep_check_many() {
#ifdef ZW_HAVE_SWEEP_SIMD
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("fma"))
        return zw_sweep_check_many_avx512;
    if (__builtin_cpu_supports("avx2")) return zw_sweep_check_many_avx2;
#endif
    return zw_sweep_check_many;
}
SweepCheck sweep_check_many() {
    static const SweepCheck chosen = choose_sweep_check_many();
    return chosen;
}

py::dict check(f64array delta, f64array alpha, f64array beta, int region, bool full) {
    const zw_region reg = region_from(region);
    Broadcast<3> bc({delta, alpha, beta});
    Result r(bc);
    VerdictOut out(r, bc, full);
    auto make_elem = [&] {
        return [&, cache = CoeffsCache()](ssize i, const std::array<double, 3> &x) mutable {
            const zw_coeffs *c;
            zw_status s = cache.get(x, &c);
            zw_verdict v;
            if (s == ZW_OK) s = zw_check_region(reg, c, x[1], x[2], &v);
            if (s == ZW_OK) out.store(i, v);
            return s;
        };
    };
    if (reg != ZW_REGION_EXACT || full) return r.finish(bc.run(r.status(), make_elem));
    // Plain "is it stable": rows with one plant go through the branch-free batch loop.
    int8_t *status = r.status();
    const ssize errors = bc.for_segments([&] {
        return [&, cache = CoeffsCache(), elem = make_elem()](const Broadcast<3>::Segment &seg) mutable {
            const zw_coeffs *c;
            if (one_plant(seg, 1) && cache.get(std::array<double, 1>{load(seg.ptr[0])}, &c) == ZW_OK &&
                zw_check_many(c, static_cast<size_t>(seg.count), as_doubles(seg.ptr[1]), seg.stride[1] / 8,
                              as_doubles(seg.ptr[2]), seg.stride[2] / 8, out.stable + seg.flat, nullptr) == ZW_OK) {
                std::memset(status + seg.flat, ZW_OK, static_cast<std::size_t>(seg.count));
                return ssize{0};
            }
            // A plant per point (a design sweep): the sweep's fields (sweep.h), as safe.
            if (one_plant(seg, 0) &&
                sweep_check_many()(static_cast<size_t>(seg.count), as_doubles(seg.ptr[0]), seg.stride[0] / 8,
                                    as_doubles(seg.ptr[1]), seg.stride[1] / 8, as_doubles(seg.ptr[2]),
                                    seg.stride[2] / 8, out.stable + seg.flat, nullptr) == ZW_OK) {
                std::memset(status + seg.flat, ZW_OK, static_cast<std::size_t>(seg.count));
                return ssize{0};
            }
            return Broadcast<3>::each(seg, status, elem);  // some element is invalid: name it
        };
    });
    return r.finish(errors);
}

// The sweep's coefficient fields per element (sweep.h; tests compare them with mpmath).
py::dict sweep_fields(f64array delta) {
    Broadcast<1> bc({delta});
    Result r(bc);
    double *e = r.add<double>(bc, "e"), *g = r.add<double>(bc, "g"), *hs = r.add<double>(bc, "hs");
    double *d12 = r.add<double>(bc, "d12"), *sigma = r.add<double>(bc, "sigma");
    const ssize errors = bc.run(r.status(), [&] {
        return [&](ssize i, const std::array<double, 1> &x) {
            zw_sweep_fields f;
            const zw_status st = zw_sweep_fields_init(&f, x[0]);
            if (st == ZW_OK) e[i] = f.e, g[i] = f.g, hs[i] = f.hs, d12[i] = f.d12, sigma[i] = f.sigma;
            return st;
        };
    });
    return r.finish(errors);
}

py::dict spectral_radius(f64array delta, f64array alpha, f64array beta) {
    return one_output<double, CoeffsCache, 3>({delta, alpha, beta}, "rho",
        [](const zw_coeffs *c, const std::array<double, 3> &x, double *rho) { return zw_spectral_radius(c, x[1], x[2], rho); });
}

py::dict radius_within(f64array delta, f64array alpha, f64array beta, f64array radius) {
    return one_output<bool, CoeffsCache, 4>({delta, alpha, beta, radius}, "within",
        [](const zw_coeffs *c, const std::array<double, 4> &x, bool *within) {
            return zw_radius_within(c, x[1], x[2], x[3], within);
        });
}

py::dict char_poly(f64array delta, f64array alpha, f64array beta) {
    Broadcast<3> bc({delta, alpha, beta});
    Result r(bc);
    double *p = r.add<double>(bc, "coefficients", {4});
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = CoeffsCache()](ssize i, const std::array<double, 3> &x) mutable {
            const zw_coeffs *c;
            zw_status s = cache.get(x, &c);
            return s != ZW_OK ? s : zw_char_poly(c, x[1], x[2], &p[4 * i]);
        };
    });
    return r.finish(errors);
}

py::dict coefficients(f64array delta) {
    Broadcast<1> bc({delta});
    Result r(bc);
    double *e = r.add<double>(bc, "e"), *c1 = r.add<double>(bc, "c1"), *c2 = r.add<double>(bc, "c2");
    double *d12 = r.add<double>(bc, "d12"), *s = r.add<double>(bc, "s"), *g = r.add<double>(bc, "g");
    const ssize errors = bc.run(r.status(), [&] {
        return [&](ssize i, const std::array<double, 1> &x) {
            zw_coeffs c;
            const zw_status st = zw_coeffs_init(&c, x[0]);
            if (st == ZW_OK) e[i] = c.e, c1[i] = c.c1, c2[i] = c.c2, d12[i] = c.d12, s[i] = c.s, g[i] = c.g;
            return st;
        };
    });
    return r.finish(errors);
}

py::dict coefficients_literal(f64array delta) {
    Broadcast<1> bc({delta});
    Result r(bc);
    double *c1 = r.add<double>(bc, "c1"), *c2 = r.add<double>(bc, "c2"), *d12 = r.add<double>(bc, "d12");
    const ssize errors = bc.run(r.status(), [&] {
        return [&](ssize i, const std::array<double, 1> &x) {
            return zw_coeffs_literal(x[0], &c1[i], &c2[i], &d12[i]);
        };
    });
    return r.finish(errors);
}

py::dict extremes(f64array delta) {
    Broadcast<1> bc({delta});
    Result r(bc);
    double *alpha_mmax = r.add<double>(bc, "alpha_mmax"), *beta_at = r.add<double>(bc, "beta_at_alpha_mmax");
    bool *at_corner = r.add<bool>(bc, "at_corner");
    double *alpha_p_max = r.add<double>(bc, "alpha_p_max"), *beta_mmax = r.add<double>(bc, "beta_mmax");
    double *beta_mmin = r.add<double>(bc, "beta_mmin"), *alpha_mmin = r.add<double>(bc, "alpha_mmin");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = CoeffsCache()](ssize i, const std::array<double, 1> &x) mutable {
            const zw_coeffs *c;
            zw_extremes ex;
            zw_status s = cache.get(x, &c);
            if (s == ZW_OK) s = zw_extremes_compute(c, &ex);
            if (s == ZW_OK) {
                alpha_mmax[i] = ex.alpha_mmax, beta_at[i] = ex.beta_at_alpha_mmax, at_corner[i] = ex.at_corner;
                alpha_p_max[i] = ex.alpha_p_max, beta_mmax[i] = ex.beta_mmax;
                beta_mmin[i] = ex.beta_mmin, alpha_mmin[i] = ex.alpha_mmin;
            }
            return s;
        };
    });
    return r.finish(errors);
}

// zw_hyperbola_top or zw_corner: (alpha, beta) of a point of the boundary against delta.
template <zw_status (*point)(const zw_coeffs *, zw_real *, zw_real *)>
py::dict boundary_point(f64array delta) {
    Broadcast<1> bc({delta});
    Result r(bc);
    double *alpha = r.add<double>(bc, "alpha"), *beta = r.add<double>(bc, "beta");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = CoeffsCache()](ssize i, const std::array<double, 1> &x) mutable {
            const zw_coeffs *c;
            zw_status s = cache.get(x, &c);
            return s != ZW_OK ? s : point(c, &alpha[i], &beta[i]);
        };
    });
    return r.finish(errors);
}

py::dict alpha_max(f64array delta, f64array beta) {
    return one_output<double, CoeffsCache, 2>({delta, beta}, "alpha_max",
        [](const zw_coeffs *c, const std::array<double, 2> &x, double *amax) { return zw_alpha_max(c, x[1], amax); });
}

py::dict beta_interval(f64array delta, f64array alpha) {
    Broadcast<2> bc({delta, alpha});
    Result r(bc);
    double *lo = r.add<double>(bc, "lo"), *hi = r.add<double>(bc, "hi");
    bool *nonempty = r.add<bool>(bc, "nonempty");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = CoeffsCache()](ssize i, const std::array<double, 2> &x) mutable {
            const zw_coeffs *c;
            zw_status s = cache.get(x, &c);
            return s != ZW_OK ? s : zw_beta_interval(c, x[1], &lo[i], &hi[i], &nonempty[i]);
        };
    });
    return r.finish(errors);
}

// ---- real units: (m, b, T) and gains (K, B) -----------------------------------------

py::dict device_normalize(f64array m, f64array b, f64array T, f64array K, f64array B) {
    Broadcast<5> bc({m, b, T, K, B});
    Result r(bc);
    double *delta = r.add<double>(bc, "delta"), *alpha = r.add<double>(bc, "alpha"), *beta = r.add<double>(bc, "beta");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = DeviceCache()](ssize i, const std::array<double, 5> &x) mutable {
            const zw_device *d;
            zw_status s = cache.get(x, &d);
            if (s == ZW_OK) s = zw_device_normalize(d, x[3], x[4], &alpha[i], &beta[i]);
            if (s == ZW_OK) delta[i] = d->co.delta;
            return s;
        };
    });
    return r.finish(errors);
}

py::dict device_check(f64array m, f64array b, f64array T, f64array K, f64array B, int region, bool full) {
    const zw_region reg = region_from(region);
    Broadcast<5> bc({m, b, T, K, B});
    Result r(bc);
    VerdictOut out(r, bc, full);
    auto make_elem = [&] {
        return [&, cache = DeviceCache()](ssize i, const std::array<double, 5> &x) mutable {
            const zw_device *d;
            zw_status s = cache.get(x, &d);
            zw_verdict v;
            if (s == ZW_OK) s = zw_device_check_region(reg, d, x[3], x[4], &v);
            if (s == ZW_OK) out.store(i, v);
            return s;
        };
    };
    if (reg != ZW_REGION_EXACT || full) return r.finish(bc.run(r.status(), make_elem));
    int8_t *status = r.status();
    const ssize errors = bc.for_segments([&] {
        return [&, cache = DeviceCache(), elem = make_elem()](const Broadcast<5>::Segment &seg) mutable {
            const zw_device *d;
            if (one_plant(seg, 3) && cache.get(std::array<double, 3>{load(seg.ptr[0]), load(seg.ptr[1]), load(seg.ptr[2])}, &d) == ZW_OK &&
                zw_device_check_many(d, static_cast<size_t>(seg.count), as_doubles(seg.ptr[3]), seg.stride[3] / 8,
                                     as_doubles(seg.ptr[4]), seg.stride[4] / 8, out.stable + seg.flat, nullptr) == ZW_OK) {
                std::memset(status + seg.flat, ZW_OK, static_cast<std::size_t>(seg.count));
                return ssize{0};
            }
            return Broadcast<5>::each(seg, status, elem);
        };
    });
    return r.finish(errors);
}

py::dict device_spectral_radius(f64array m, f64array b, f64array T, f64array K, f64array B) {
    return one_output<double, DeviceCache, 5>({m, b, T, K, B}, "rho",
        [](const zw_device *d, const std::array<double, 5> &x, double *rho) {
            return zw_device_spectral_radius(d, x[3], x[4], rho);
        });
}

py::dict device_radius_within(f64array m, f64array b, f64array T, f64array K, f64array B, f64array radius) {
    return one_output<bool, DeviceCache, 6>({m, b, T, K, B, radius}, "within",
        [](const zw_device *d, const std::array<double, 6> &x, bool *within) {
            return zw_device_radius_within(d, x[3], x[4], x[5], within);
        });
}

py::dict device_extremes(f64array m, f64array b, f64array T) {
    Broadcast<3> bc({m, b, T});
    Result r(bc);
    double *K_mmax = r.add<double>(bc, "K_mmax"), *B_at = r.add<double>(bc, "B_at_K_mmax");
    bool *at_corner = r.add<bool>(bc, "at_corner");
    double *K_p_max = r.add<double>(bc, "K_p_max"), *B_mmax = r.add<double>(bc, "B_mmax");
    double *B_mmin = r.add<double>(bc, "B_mmin"), *K_mmin = r.add<double>(bc, "K_mmin");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = DeviceCache()](ssize i, const std::array<double, 3> &x) mutable {
            const zw_device *d;
            zw_device_extremes ex;
            zw_status s = cache.get(x, &d);
            if (s == ZW_OK) s = zw_device_extremes_compute(d, &ex);
            if (s == ZW_OK) {
                K_mmax[i] = ex.K_mmax, B_at[i] = ex.B_at_K_mmax, at_corner[i] = ex.at_corner;
                K_p_max[i] = ex.K_p_max, B_mmax[i] = ex.B_mmax, B_mmin[i] = ex.B_mmin, K_mmin[i] = ex.K_mmin;
            }
            return s;
        };
    });
    return r.finish(errors);
}

py::dict device_k_max(f64array m, f64array b, f64array T, f64array B) {
    return one_output<double, DeviceCache, 4>({m, b, T, B}, "K_max",
        [](const zw_device *d, const std::array<double, 4> &x, double *kmax) { return zw_device_k_max(d, x[3], kmax); });
}

py::dict device_b_range(f64array m, f64array b, f64array T, f64array K) {
    Broadcast<4> bc({m, b, T, K});
    Result r(bc);
    double *lo = r.add<double>(bc, "lo"), *hi = r.add<double>(bc, "hi");
    bool *nonempty = r.add<bool>(bc, "nonempty");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = DeviceCache()](ssize i, const std::array<double, 4> &x) mutable {
            const zw_device *d;
            zw_status s = cache.get(x, &d);
            return s != ZW_OK ? s : zw_device_b_range(d, x[3], &lo[i], &hi[i], &nonempty[i]);
        };
    });
    return r.finish(errors);
}

py::dict device_influence(f64array m, f64array b, f64array T) {
    Broadcast<3> bc({m, b, T});
    Result r(bc);
    const char *real_names[] = {"delta", "K_mmax", "B_mmax", "m_K1", "m_K2", "K_mmax_at_m_K2",
                                "K_mmax_at_m_K1", "m_K_match", "T_B", "T_0", "m_0", "m_B",
                                "b_0", "b_BB", "best_m_for_K"};
    const char *trend_names[] = {"K_vs_m", "K_vs_b", "K_vs_T", "B_vs_m", "B_vs_b", "B_vs_T"};
    std::array<double *, 15> reals;
    std::array<int8_t *, 6> trends;
    for (std::size_t k = 0; k < reals.size(); ++k) reals[k] = r.add<double>(bc, real_names[k]);
    for (std::size_t k = 0; k < trends.size(); ++k) trends[k] = r.add<int8_t>(bc, trend_names[k]);
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = DeviceCache()](ssize i, const std::array<double, 3> &x) mutable {
            const zw_device *d;
            zw_influence f;
            zw_status s = cache.get(x, &d);
            if (s == ZW_OK) s = zw_device_influence(d, &f);
            if (s != ZW_OK) return s;
            const double values[] = {f.delta, f.K_mmax, f.B_mmax, f.m_K1, f.m_K2, f.K_mmax_at_m_K2,
                                     f.K_mmax_at_m_K1, f.m_K_match, f.T_B, f.T_0, f.m_0, f.m_B,
                                     f.b_0, f.b_BB, f.best_m_for_K};
            const zw_trend signs[] = {f.K_vs_m, f.K_vs_b, f.K_vs_T, f.B_vs_m, f.B_vs_b, f.B_vs_T};
            for (std::size_t k = 0; k < reals.size(); ++k) reals[k][i] = values[k];
            for (std::size_t k = 0; k < trends.size(); ++k) trends[k][i] = static_cast<int8_t>(signs[k]);
            return s;
        };
    });
    return r.finish(errors);
}


// No plant: for kernels whose inputs are all per-element arguments.
struct NoPlant {
    using plant_type = void;
    template <std::size_t N>
    zw_status get(const std::array<double, N> &, const void **out) {
        *out = nullptr;
        return ZW_OK;
    }
};

// ---- the general loop (loop.h): delay, velocity filter, differentiator ----------------
//
// The loop's kind (delay, differentiator, filter kind, average length) is one per call;
// the filter's parameter broadcasts like a plant parameter: the pole a in the normalized
// space, the cut-off f_c [Hz] in real units (a = zw_loop_lowpass_pole(f_c, T) per
// element).  A zw_loop is built once per (delta, a) or (m, b, T, f_c) and reused.

struct LoopKind {
    unsigned delay;
    zw_differentiator differentiator;
    zw_velocity_filter filter;
    unsigned average;
    bool pole_given = false;  // devices: the filter input is the pole a, not the cut-off f_c
};

// Range checks are the C core's (ZW_ERR_DELAY, ZW_ERR_FILTER per element); here only
// what cannot be represented in the enums.
LoopKind loop_kind(long delay, int differentiator, int filter, long average) {
    if (differentiator != ZW_DIFF_BACKWARD && differentiator != ZW_DIFF_TUSTIN)
        throw py::value_error("unknown differentiator " + std::to_string(differentiator));
    if (filter != ZW_VFILTER_NONE && filter != ZW_VFILTER_LOWPASS && filter != ZW_VFILTER_AVERAGE)
        throw py::value_error("unknown velocity filter " + std::to_string(filter));
    LoopKind k;
    // Negative or huge values become a value zw_loop_init refuses (ZW_ERR_DELAY / FILTER).
    k.delay = delay < 0 || delay > 1000 ? 1000u : static_cast<unsigned>(delay);
    k.average = average < 0 || average > 1000 ? 1000u : static_cast<unsigned>(average);
    k.differentiator = static_cast<zw_differentiator>(differentiator);
    k.filter = static_cast<zw_velocity_filter>(filter);
    return k;
}

zw_loop_spec loop_spec(const LoopKind &k, double pole) {
    zw_loop_spec s{};
    s.delay = k.delay;
    s.differentiator = k.differentiator;
    s.filter = k.filter;
    s.filter_pole = k.filter == ZW_VFILTER_LOWPASS ? pole : 0.0;
    s.average = k.filter == ZW_VFILTER_AVERAGE ? k.average : 0u;
    return s;
}

// The loop of one (delta, pole, kappa, lambda) element: the ideal plant's coefficients
// (zw_coeffs_init + zw_loop_init) when kappa = lambda = 0, else the plant of plant.h
// (zw_plant_init + zw_loop_init_plant; the normalized inputs are taken as exact).
class NormalizedLoopCache {
  public:
    using plant_type = zw_loop;
    explicit NormalizedLoopCache(const LoopKind &kind) : kind_(kind) {}

    template <std::size_t N>
    zw_status get(const std::array<double, N> &x, const zw_loop **out) {
        if (!valid_ || std::memcmp(key_.data(), x.data(), sizeof key_) != 0) {
            std::memcpy(key_.data(), x.data(), sizeof key_);
            valid_ = true;
            status_ = build();
        }
        *out = &loop_;
        return status_;
    }

  private:
    zw_status build() {
        const zw_loop_spec spec = loop_spec(kind_, key_[1]);
        if (kind_.filter == ZW_VFILTER_LOWPASS && std::isnan(key_[1])) return ZW_ERR_NAN;
        if (key_[2] == 0.0 && key_[3] == 0.0) {
            zw_coeffs c;
            const zw_status s = zw_coeffs_init(&c, key_[0]);
            return s != ZW_OK ? s : zw_loop_init(&loop_, &c, &spec);
        }
        zw_plant_spec ps{};
        ps.delta = key_[0];
        ps.kappa = key_[2];
        ps.lambda = key_[3];
        const zw_status s = zw_plant_init(&plant_, &ps);
        return s != ZW_OK ? s : zw_loop_init_plant(&loop_, &plant_, &spec);
    }

    LoopKind kind_;
    bool valid_ = false;
    std::array<double, 4> key_{};
    zw_status status_ = ZW_OK;
    zw_plant plant_{};
    zw_loop loop_{};
};

// The loop of one (m, b, T, f_c, k_p, tau, m_h, b_h, k_h) element: zw_device_loop, whose
// loop carries the rounding of K / (M/T^2) and B / (M/T) in its guard
// (zw_loop_carry_gain_rounding); zw_device_loop_init_plant when a plant-side part (a
// stiffness, an actuator lag, a hand) is present, else zw_device_loop_init.
class DeviceLoopCache {
  public:
    using Plant = zw_device_loop;
    using plant_type = Plant;
    explicit DeviceLoopCache(const LoopKind &kind) : kind_(kind) {}

    template <std::size_t N>
    zw_status get(const std::array<double, N> &x, const Plant **out) {
        if (!valid_ || std::memcmp(key_.data(), x.data(), sizeof key_) != 0) {
            std::memcpy(key_.data(), x.data(), sizeof key_);
            valid_ = true;
            status_ = build();
        }
        *out = &plant_;
        return status_;
    }

  private:
    zw_status build() {
        zw_device_loop_spec spec{};
        spec.delay = kind_.delay;
        spec.differentiator = kind_.differentiator;
        spec.filter = kind_.filter;
        spec.average = kind_.filter == ZW_VFILTER_AVERAGE ? kind_.average : 0u;
        const bool lowpass = kind_.filter == ZW_VFILTER_LOWPASS;
        if (lowpass && kind_.pole_given) spec.pole = key_[3];  // zw_loop_init checks 0 <= a < 1, NaN
        if (lowpass && !kind_.pole_given) spec.cutoff_hz = key_[3];
        const bool parts = key_[4] != 0.0 || key_[5] != 0.0 || key_[6] != 0.0 || key_[7] != 0.0 || key_[8] != 0.0;
        const zw_status s = parts ? zw_device_loop_init_plant(&plant_, key_[0], key_[1], key_[2], key_[4], key_[5],
                                                              key_[6], key_[7], key_[8], &spec)
                                  : zw_device_loop_init(&plant_, key_[0], key_[1], key_[2], &spec);
        // cut-off 0 would mean "take the pole" in C; here it is a bad cut-off
        if (s == ZW_OK && lowpass && !kind_.pole_given && key_[3] == 0.0) return ZW_ERR_FILTER;
        return s;
    }

    LoopKind kind_;
    bool valid_ = false;
    std::array<double, 9> key_{};
    zw_status status_ = ZW_OK;
    Plant plant_{};
};

// One element's call: the normalized loop at (alpha, beta), or the device's loop at (K, B)
// through device_loop.h, which normalizes and carries (or refuses) the conversion.  Each
// call has its own scratch (loop.h's zw_loop_workspace, about 1 KB: the host stack is
// large, and no two calls, on whatever threads, share one).
zw_status check_of(const zw_loop *l, double a, double b, zw_loop_verdict *v) {
    zw_loop_workspace ws;
    return zw_loop_check(l, &ws, a, b, v);
}
zw_status check_of(const zw_device_loop *p, double K, double B, zw_loop_verdict *v) {
    zw_loop_workspace ws;
    return zw_device_loop_check(p, &ws, K, B, v);
}
// The verdict alone (the fast path: no root run for the deciding boundary of an unstable point).
zw_status stable_of(const zw_loop *l, double a, double b, bool *stable) {
    zw_loop_workspace ws;
    return zw_loop_is_stable(l, &ws, a, b, stable);
}
zw_status stable_of(const zw_device_loop *p, double K, double B, bool *stable) {
    zw_loop_workspace ws;
    return zw_device_loop_is_stable(p, &ws, K, B, stable);
}
zw_status radius_of(const zw_loop *l, double a, double b, double *rho, double *theta) {
    zw_loop_workspace ws;
    return zw_loop_spectral_radius(l, &ws, a, b, rho, theta);
}
zw_status radius_of(const zw_device_loop *p, double K, double B, double *rho, double *theta) {
    zw_loop_workspace ws;
    return zw_device_loop_spectral_radius(p, &ws, K, B, rho, theta);
}
zw_status within_of(const zw_loop *l, double a, double b, double r, bool *within) {
    zw_loop_workspace ws;
    return zw_loop_radius_within(l, &ws, a, b, r, within);
}
zw_status within_of(const zw_device_loop *p, double K, double B, double r, bool *within) {
    zw_loop_workspace ws;
    return zw_device_loop_radius_within(p, &ws, K, B, r, within);
}

// Inputs: 4 plant keys (delta, pole, kappa, lambda) or 9 (m, b, T, f_c and the parts), then the two gains (alpha, beta
// or K, B), then extras; fn(plant, i, gain1, gain2, inputs).
template <class Cache, std::size_t Keys, std::size_t N, class Fn, class Setup>
py::dict loop_kernel(const std::array<f64array, N> &inputs, const LoopKind &kind, Fn fn, Setup setup) {
    Broadcast<N> bc(inputs);
    Result r(bc);
    setup(r, bc);
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = Cache(kind)](ssize i, const std::array<double, N> &x) mutable {
            const typename Cache::plant_type *p;
            const zw_status s = cache.get(x, &p);
            return s != ZW_OK ? s : fn(p, i, x[Keys], x[Keys + 1], x);
        };
    });
    return r.finish(errors);
}

struct LoopVerdictOut {
    bool *stable = nullptr, *marginal = nullptr;
    uint8_t *boundary = nullptr;
    double *theta = nullptr;
};

template <class Cache, std::size_t Keys>
py::dict loop_check_kernel(const std::array<f64array, Keys + 2> &inputs, const LoopKind &kind, bool full) {
    constexpr std::size_t N = Keys + 2;
    LoopVerdictOut out;
    return loop_kernel<Cache, Keys, N>(inputs, kind,
        [&out](const auto *p, ssize i, double g1, double g2, const std::array<double, N> &) {
            if (!out.marginal) return stable_of(p, g1, g2, &out.stable[i]); // "stable" only
            zw_loop_verdict v;
            const zw_status s = check_of(p, g1, g2, &v);
            if (s != ZW_OK) return s;
            out.stable[i] = v.stable;
            if (out.marginal) {
                out.marginal[i] = v.marginal;
                out.boundary[i] = static_cast<uint8_t>(v.deciding);
                out.theta[i] = v.theta;
            }
            return s;
        },
        [&out, full](Result &r, const Broadcast<N> &bc) {
            out.stable = r.add<bool>(bc, "stable");
            if (!full) return;
            out.marginal = r.add<bool>(bc, "marginal");
            out.boundary = r.add<uint8_t>(bc, "boundary");
            out.theta = r.add<double>(bc, "theta");
        });
}

template <class Cache, std::size_t Keys>
py::dict loop_radius_kernel(const std::array<f64array, Keys + 2> &inputs, const LoopKind &kind) {
    constexpr std::size_t N = Keys + 2;
    double *rho = nullptr, *theta = nullptr;
    return loop_kernel<Cache, Keys, N>(inputs, kind,
        [&](const auto *p, ssize i, double g1, double g2, const std::array<double, N> &) {
            return radius_of(p, g1, g2, &rho[i], &theta[i]);
        },
        [&](Result &r, const Broadcast<N> &bc) {
            rho = r.add<double>(bc, "rho");
            theta = r.add<double>(bc, "theta");
        });
}

template <class Cache, std::size_t Keys>
py::dict loop_within_kernel(const std::array<f64array, Keys + 3> &inputs, const LoopKind &kind) {
    constexpr std::size_t N = Keys + 3;
    bool *within = nullptr;
    return loop_kernel<Cache, Keys, N>(inputs, kind,
        [&](const auto *p, ssize i, double g1, double g2, const std::array<double, N> &x) {
            return within_of(p, g1, g2, x[Keys + 2], &within[i]);
        },
        [&](Result &r, const Broadcast<N> &bc) { within = r.add<bool>(bc, "within"); });
}

// p(z) right-aligned in ZW_LOOP_MAX_DEGREE + 1 entries (leading zeros above the degree),
// so every element has the same layout; "degree" per element.
template <class Cache, std::size_t Keys>
py::dict loop_poly_kernel(const std::array<f64array, Keys + 2> &inputs, const LoopKind &kind) {
    constexpr std::size_t N = Keys + 2;
    constexpr ssize width = ZW_LOOP_MAX_DEGREE + 1;
    double *coef = nullptr;
    uint8_t *degree = nullptr;
    return loop_kernel<Cache, Keys, N>(inputs, kind,
        [&](const zw_loop *l, ssize i, double alpha, double beta, const std::array<double, N> &) {
            double p[ZW_LOOP_MAX_DEGREE + 1u];
            unsigned deg = 0;
            const zw_status s = zw_loop_poly(l, alpha, beta, p, &deg);
            if (s != ZW_OK) return s;
            double *row = coef + width * i;
            std::fill(row, row + width, 0.0);
            std::copy(p, p + deg + 1, row + (width - 1 - static_cast<ssize>(deg)));
            degree[i] = static_cast<uint8_t>(deg);
            return s;
        },
        [&](Result &r, const Broadcast<N> &bc) {
            coef = r.add<double>(bc, "coefficients", {width});
            degree = r.add<uint8_t>(bc, "degree");
        });
}

using NLC = NormalizedLoopCache;
using DLC = DeviceLoopCache;

#define ZW_NPLANT f64array kappa, f64array lambda
py::dict loop_check(f64array delta, f64array pole, ZW_NPLANT, f64array alpha, f64array beta, long delay, int diff,
                    int filter, long average, bool full) {
    return loop_check_kernel<NLC, 4>({delta, pole, kappa, lambda, alpha, beta}, loop_kind(delay, diff, filter, average), full);
}
py::dict loop_spectral_radius(f64array delta, f64array pole, ZW_NPLANT, f64array alpha, f64array beta, long delay,
                              int diff, int filter, long average) {
    return loop_radius_kernel<NLC, 4>({delta, pole, kappa, lambda, alpha, beta}, loop_kind(delay, diff, filter, average));
}
py::dict loop_radius_within(f64array delta, f64array pole, ZW_NPLANT, f64array alpha, f64array beta,
                            f64array radius, long delay, int diff, int filter, long average) {
    return loop_within_kernel<NLC, 4>({delta, pole, kappa, lambda, alpha, beta, radius}, loop_kind(delay, diff, filter, average));
}
py::dict loop_poly(f64array delta, f64array pole, ZW_NPLANT, f64array alpha, f64array beta, long delay, int diff,
                   int filter, long average) {
    return loop_poly_kernel<NLC, 4>({delta, pole, kappa, lambda, alpha, beta}, loop_kind(delay, diff, filter, average));
}
LoopKind device_kind(long delay, int diff, int filter, long average, bool pole_given) {
    LoopKind k = loop_kind(delay, diff, filter, average);
    k.pole_given = pole_given;
    return k;
}

#define ZW_PARTS f64array k_p, f64array tau, f64array m_h, f64array b_h, f64array k_h
py::dict device_loop_check(f64array m, f64array b, f64array T, f64array cutoff, ZW_PARTS, f64array K, f64array B,
                           long delay, int diff, int filter, long average, bool pole_given, bool full) {
    return loop_check_kernel<DLC, 9>({m, b, T, cutoff, k_p, tau, m_h, b_h, k_h, K, B},
                                     device_kind(delay, diff, filter, average, pole_given), full);
}
py::dict device_loop_spectral_radius(f64array m, f64array b, f64array T, f64array cutoff, ZW_PARTS, f64array K,
                                     f64array B, long delay, int diff, int filter, long average, bool pole_given) {
    return loop_radius_kernel<DLC, 9>({m, b, T, cutoff, k_p, tau, m_h, b_h, k_h, K, B},
                                      device_kind(delay, diff, filter, average, pole_given));
}
py::dict device_loop_radius_within(f64array m, f64array b, f64array T, f64array cutoff, ZW_PARTS, f64array K,
                                   f64array B, f64array radius, long delay, int diff, int filter, long average,
                                   bool pole_given) {
    return loop_within_kernel<DLC, 9>({m, b, T, cutoff, k_p, tau, m_h, b_h, k_h, K, B, radius},
                                      device_kind(delay, diff, filter, average, pole_given));
}

py::dict loop_lowpass_pole(f64array cutoff, f64array T) {
    return one_output<double, NoPlant, 2>({cutoff, T}, "pole",
        [](const void *, const std::array<double, 2> &x, double *a) { return zw_loop_lowpass_pole(x[0], x[1], a); });
}


// ---- limits of the general loop (loop_limits.h) --------------------------------------
//
// Device limits: zw_device_loop's certified real-unit limits (device_loop.h).

py::dict loop_alpha_max(f64array delta, f64array pole, ZW_NPLANT, f64array beta, long delay, int diff, int filter,
                        long average) {
    const LoopKind kind = loop_kind(delay, diff, filter, average);
    Broadcast<5> bc({delta, pole, kappa, lambda, beta});
    Result r(bc);
    double *out = r.add<double>(bc, "alpha_max");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = NLC(kind), ws = zw_loop_workspace{}](ssize i, const std::array<double, 5> &x) mutable {
            const zw_loop *l;
            const zw_status s = cache.get(x, &l);
            return s != ZW_OK ? s : zw_loop_alpha_max(l, &ws, x[4], &out[i]);
        };
    });
    return r.finish(errors);
}

py::dict loop_beta_interval(f64array delta, f64array pole, ZW_NPLANT, f64array alpha, long delay, int diff,
                            int filter, long average) {
    const LoopKind kind = loop_kind(delay, diff, filter, average);
    Broadcast<5> bc({delta, pole, kappa, lambda, alpha});
    Result r(bc);
    double *lo = r.add<double>(bc, "lo"), *hi = r.add<double>(bc, "hi");
    bool *nonempty = r.add<bool>(bc, "nonempty");
    uint8_t *count = r.add<uint8_t>(bc, "count");
    bool *truncated = r.add<bool>(bc, "truncated");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = NLC(kind), ws = zw_loop_workspace{}](ssize i, const std::array<double, 5> &x) mutable {
            const zw_loop *l;
            zw_status s = cache.get(x, &l);
            zw_loop_beta_set set;
            if (s == ZW_OK) s = zw_loop_beta_intervals(l, &ws, x[4], &set);
            if (s == ZW_OK) s = zw_loop_beta_interval(l, &ws, x[4], &lo[i], &hi[i], &nonempty[i]);
            if (s == ZW_OK) count[i] = static_cast<uint8_t>(set.count), truncated[i] = set.truncated;
            return s;
        };
    });
    return r.finish(errors);
}

py::dict loop_extremes(f64array delta, f64array pole, ZW_NPLANT, long delay, int diff, int filter, long average) {
    const LoopKind kind = loop_kind(delay, diff, filter, average);
    Broadcast<4> bc({delta, pole, kappa, lambda});
    Result r(bc);
    double *amax = r.add<double>(bc, "alpha_mmax"), *bat = r.add<double>(bc, "beta_at_alpha_mmax");
    double *apmax = r.add<double>(bc, "alpha_p_max"), *bmax = r.add<double>(bc, "beta_mmax");
    double *bmin = r.add<double>(bc, "beta_mmin");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = NLC(kind), ws = zw_loop_workspace{}](ssize i, const std::array<double, 4> &x) mutable {
            const zw_loop *l;
            zw_status s = cache.get(x, &l);
            zw_loop_extremes ex;
            if (s == ZW_OK) s = zw_loop_extremes_compute(l, &ws, &ex);
            if (s == ZW_OK)
                amax[i] = ex.alpha_mmax, bat[i] = ex.beta_at_alpha_mmax, apmax[i] = ex.alpha_p_max,
                bmax[i] = ex.beta_mmax, bmin[i] = ex.beta_mmin;
            return s;
        };
    });
    return r.finish(errors);
}

py::dict loop_boundary_point(f64array delta, f64array pole, ZW_NPLANT, f64array theta, long delay, int diff,
                             int filter, long average) {
    const LoopKind kind = loop_kind(delay, diff, filter, average);
    Broadcast<5> bc({delta, pole, kappa, lambda, theta});
    Result r(bc);
    double *alpha = r.add<double>(bc, "alpha"), *beta = r.add<double>(bc, "beta");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = NLC(kind)](ssize i, const std::array<double, 5> &x) mutable {
            const zw_loop *l;
            const zw_status s = cache.get(x, &l);
            return s != ZW_OK ? s : zw_loop_boundary_point(l, x[4], &alpha[i], &beta[i]);
        };
    });
    return r.finish(errors);
}

py::dict device_loop_k_max(f64array m, f64array b, f64array T, f64array cutoff, ZW_PARTS, f64array B, long delay,
                           int diff, int filter, long average, bool pole_given) {
    const LoopKind kind = device_kind(delay, diff, filter, average, pole_given);
    Broadcast<10> bc({m, b, T, cutoff, k_p, tau, m_h, b_h, k_h, B});
    Result r(bc);
    double *out = r.add<double>(bc, "K_max");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = DLC(kind), ws = zw_loop_workspace{}](ssize i, const std::array<double, 10> &x) mutable {
            const zw_device_loop *p;
            const zw_status s = cache.get(x, &p);
            return s != ZW_OK ? s : zw_device_loop_k_max(p, &ws, x[9], &out[i]);
        };
    });
    return r.finish(errors);
}

py::dict device_loop_b_range(f64array m, f64array b, f64array T, f64array cutoff, ZW_PARTS, f64array K, long delay,
                             int diff, int filter, long average, bool pole_given) {
    const LoopKind kind = device_kind(delay, diff, filter, average, pole_given);
    Broadcast<10> bc({m, b, T, cutoff, k_p, tau, m_h, b_h, k_h, K});
    Result r(bc);
    double *lo = r.add<double>(bc, "lo"), *hi = r.add<double>(bc, "hi");
    bool *nonempty = r.add<bool>(bc, "nonempty");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = DLC(kind), ws = zw_loop_workspace{}](ssize i, const std::array<double, 10> &x) mutable {
            const zw_device_loop *p;
            const zw_status s = cache.get(x, &p);
            return s != ZW_OK ? s : zw_device_loop_b_range(p, &ws, x[9], &lo[i], &hi[i], &nonempty[i]);
        };
    });
    return r.finish(errors);
}

py::dict device_loop_extremes(f64array m, f64array b, f64array T, f64array cutoff, ZW_PARTS, long delay, int diff,
                              int filter, long average, bool pole_given) {
    const LoopKind kind = device_kind(delay, diff, filter, average, pole_given);
    Broadcast<9> bc({m, b, T, cutoff, k_p, tau, m_h, b_h, k_h});
    Result r(bc);
    double *K_mmax = r.add<double>(bc, "K_mmax"), *B_at = r.add<double>(bc, "B_at_K_mmax");
    double *K_p_max = r.add<double>(bc, "K_p_max"), *B_mmax = r.add<double>(bc, "B_mmax");
    double *B_mmin = r.add<double>(bc, "B_mmin");
    const ssize errors = bc.run(r.status(), [&] {
        return [&, cache = DLC(kind), ws = zw_loop_workspace{}](ssize i, const std::array<double, 9> &x) mutable {
            const zw_device_loop *p;
            zw_status s = cache.get(x, &p);
            zw_device_loop_extremes ex;
            if (s == ZW_OK) s = zw_device_loop_extremes_compute(p, &ws, &ex);
            if (s == ZW_OK)
                K_mmax[i] = ex.K_mmax, B_at[i] = ex.B_at_K_mmax, K_p_max[i] = ex.K_p_max, B_mmax[i] = ex.B_mmax,
                B_mmin[i] = ex.B_mmin;
            return s;
        };
    });
    return r.finish(errors);
}

}  // namespace

void zw_register_sim(py::module_ &mod);  // zwidth_sim.cpp: Simulator, sim_judge, SIM_EFFECTS
void zw_register_box(py::module_ &mod);  // below: certification over a plant box (box.h)

PYBIND11_MODULE(_core, mod) {
    mod.doc() =
        "zwidth's C core (double precision) as broadcasting kernels.  Private: use the "
        "functions of the zwidth package, which name invalid parameters in their errors.";

    mod.attr("VERSION") = ZW_VERSION_STRING;

    py::dict status_names;
    for (int s = ZW_OK; s <= ZW_STATUS_LAST; ++s) status_names[py::int_(s)] = zw_status_name(static_cast<zw_status>(s));
    mod.attr("STATUS_NAMES") = status_names;

    py::dict regions;
    regions["exact"] = int{ZW_REGION_EXACT};
    regions["legacy"] = int{ZW_REGION_LEGACY};
    regions["passivity"] = int{ZW_REGION_PASSIVITY};
    regions["delta0"] = int{ZW_REGION_DELTA0};
    regions["delta_inf"] = int{ZW_REGION_DELTA_INF};
    regions["small"] = int{ZW_REGION_SMALL};
    mod.attr("REGIONS") = regions;

    py::dict bounds;
    bounds["damping"] = int{ZW_BOUND_DAMPING};
    bounds["stiffness"] = int{ZW_BOUND_STIFFNESS};
    bounds["hyperbola"] = int{ZW_BOUND_HYPERBOLA};
    bounds["line"] = int{ZW_BOUND_LINE};
    bounds["passivity"] = int{ZW_BOUND_PASSIVITY};
    mod.attr("BOUNDS") = bounds;

    py::dict constants;
    constants["DELTA0"] = ZW_DELTA0;
    constants["DELTA1"] = ZW_DELTA1;
    constants["DELTA2"] = ZW_DELTA2;
    constants["DELTA_K1"] = ZW_DELTA_K1;
    constants["DELTA_K2"] = ZW_DELTA_K2;
    constants["DELTA_B"] = ZW_DELTA_B;
    constants["DELTA_BB"] = ZW_DELTA_BB;
    constants["DELTA_KM"] = ZW_DELTA_KM;
    constants["KMAX_LOCAL_MAX"] = ZW_KMAX_LOCAL_MAX;
    constants["KMAX_LOCAL_MIN"] = ZW_KMAX_LOCAL_MIN;
    mod.attr("CONSTANTS") = constants;

    const auto d = py::arg("delta"), a = py::arg("alpha"), be = py::arg("beta");
    const auto m = py::arg("m"), b = py::arg("b"), T = py::arg("T"), K = py::arg("K"), B = py::arg("B");
    mod.def("check", &check, d, a, be, py::arg("region"), py::arg("full"), "zw_check_region per element.");
    mod.def("spectral_radius", &spectral_radius, d, a, be, "zw_spectral_radius per element.");
    mod.def("radius_within", &radius_within, d, a, be, py::arg("radius"), "zw_radius_within per element.");
    mod.def("char_poly", &char_poly, d, a, be, "zw_char_poly per element (trailing axis of 4).");
    mod.def("coefficients", &coefficients, d, "zw_coeffs_init per element.");
    mod.def("sweep_fields", &sweep_fields, d, "zw_sweep_fields_init per element (the per-plant sweep's fields).");
    mod.def("coefficients_literal", &coefficients_literal, d, "zw_coeffs_literal per element.");
    mod.def("extremes", &extremes, d, "zw_extremes_compute per element.");
    mod.def("hyperbola_top", &boundary_point<zw_hyperbola_top>, d, "zw_hyperbola_top per element.");
    mod.def("corner", &boundary_point<zw_corner>, d, "zw_corner per element.");
    mod.def("alpha_max", &alpha_max, d, be, "zw_alpha_max per element.");
    mod.def("beta_interval", &beta_interval, d, a, "zw_beta_interval per element.");
    mod.def("device_normalize", &device_normalize, m, b, T, K, B, "zw_device_normalize per element.");
    mod.def("device_check", &device_check, m, b, T, K, B, py::arg("region"), py::arg("full"),
            "zw_device_check_region per element.");
    mod.def("device_spectral_radius", &device_spectral_radius, m, b, T, K, B,
            "zw_device_spectral_radius per element.");
    mod.def("device_radius_within", &device_radius_within, m, b, T, K, B, py::arg("radius"),
            "zw_device_radius_within per element.");
    mod.def("device_extremes", &device_extremes, m, b, T, "zw_device_extremes_compute per element.");
    mod.def("device_k_max", &device_k_max, m, b, T, B, "zw_device_k_max per element.");
    mod.def("device_b_range", &device_b_range, m, b, T, K, "zw_device_b_range per element.");
    mod.def("device_influence", &device_influence, m, b, T, "zw_device_influence per element.");
    py::dict boundaries;
    boundaries["none"] = int{ZW_LOOP_BOUNDARY_NONE};
    boundaries["z=1"] = int{ZW_LOOP_BOUNDARY_Z_PLUS1};
    boundaries["z=-1"] = int{ZW_LOOP_BOUNDARY_Z_MINUS1};
    boundaries["complex"] = int{ZW_LOOP_BOUNDARY_COMPLEX};
    mod.attr("LOOP_BOUNDARIES") = boundaries;
    py::dict differentiators;
    differentiators["backward"] = int{ZW_DIFF_BACKWARD};
    differentiators["tustin"] = int{ZW_DIFF_TUSTIN};
    mod.attr("LOOP_DIFFERENTIATORS") = differentiators;
    py::dict filters;
    filters["none"] = int{ZW_VFILTER_NONE};
    filters["lowpass"] = int{ZW_VFILTER_LOWPASS};
    filters["average"] = int{ZW_VFILTER_AVERAGE};
    mod.attr("LOOP_FILTERS") = filters;
    mod.attr("LOOP_MAX_DELAY") = int{ZW_LOOP_MAX_DELAY};
    mod.attr("LOOP_MAX_AVERAGE") = int{ZW_LOOP_MAX_AVERAGE};
    mod.attr("LOOP_MAX_DEGREE") = int{ZW_LOOP_MAX_DEGREE};
    // the normalized plant (plant.h): kappa = Kp T^2 / M, lambda = tau / T; both 0 is the ideal plant
    const auto kap = py::arg("kappa"), lam = py::arg("lambda_");
    const auto pole = py::arg("pole"), fc = py::arg("cutoff"), dl = py::arg("delay"), df = py::arg("differentiator"),
               fl = py::arg("filter"), av = py::arg("average");
    mod.def("loop_check", &loop_check, d, pole, kap, lam, a, be, dl, df, fl, av, py::arg("full"), "zw_loop_check per element.");
    mod.def("loop_spectral_radius", &loop_spectral_radius, d, pole, kap, lam, a, be, dl, df, fl, av,
            "zw_loop_spectral_radius per element (rho, theta).");
    mod.def("loop_radius_within", &loop_radius_within, d, pole, kap, lam, a, be, py::arg("radius"), dl, df, fl, av,
            "zw_loop_radius_within per element.");
    mod.def("loop_poly", &loop_poly, d, pole, kap, lam, a, be, dl, df, fl, av,
            "zw_loop_poly per element (right-aligned in LOOP_MAX_DEGREE + 1 entries, and the degree).");
    const auto pg = py::arg("pole_given");
    // the plant-side parts (device_loop.h, zw_device_loop_init_plant): all 0 is the plain plant
    const auto kp = py::arg("k_p"), tau = py::arg("tau"), mh = py::arg("m_h"), bh = py::arg("b_h"), kh = py::arg("k_h");
    mod.def("device_loop_check", &device_loop_check, m, b, T, fc, kp, tau, mh, bh, kh, K, B, dl, df, fl, av, pg, py::arg("full"),
            "zw_loop_check of the device's loop per element (gain rounding in the guard).");
    mod.def("device_loop_spectral_radius", &device_loop_spectral_radius, m, b, T, fc, kp, tau, mh, bh, kh, K, B, dl, df, fl, av, pg,
            "zw_loop_spectral_radius of the device's loop per element.");
    mod.def("device_loop_radius_within", &device_loop_radius_within, m, b, T, fc, kp, tau, mh, bh, kh, K, B, py::arg("radius"), dl, df, fl,
            av, pg, "zw_loop_radius_within of the device's loop per element.");
    mod.def("loop_lowpass_pole", &loop_lowpass_pole, py::arg("cutoff"), T, "zw_loop_lowpass_pole per element.");
    mod.def("loop_alpha_max", &loop_alpha_max, d, pole, kap, lam, be, dl, df, fl, av, "zw_loop_alpha_max per element.");
    mod.def("loop_beta_interval", &loop_beta_interval, d, pole, kap, lam, a, dl, df, fl, av,
            "zw_loop_beta_interval (the widest) and the count of zw_loop_beta_intervals per element.");
    mod.def("loop_extremes", &loop_extremes, d, pole, kap, lam, dl, df, fl, av, "zw_loop_extremes_compute per element.");
    mod.def("loop_boundary_point", &loop_boundary_point, d, pole, kap, lam, py::arg("theta"), dl, df, fl, av,
            "zw_loop_boundary_point per element.");
    mod.def("device_loop_k_max", &device_loop_k_max, m, b, T, fc, kp, tau, mh, bh, kh, B, dl, df, fl, av, pg,
            "K_max of the device's loop per element (certified, pulled inward for the conversions).");
    mod.def("device_loop_b_range", &device_loop_b_range, m, b, T, fc, kp, tau, mh, bh, kh, K, dl, df, fl, av, pg,
            "the widest stable B interval of the device's loop per element.");
    mod.def("device_loop_extremes", &device_loop_extremes, m, b, T, fc, kp, tau, mh, bh, kh, dl, df, fl, av, pg,
            "zw_loop_extremes_compute of the device's loop, real units, per element.");
    zw_register_sim(mod);
    zw_register_box(mod);
}

// ---- certification over a plant box (box.h) -----------------------------------------------
// Scalar calls (one branch and bound each), without the GIL; the work list is a vector
// owned here.  Each returns a dict with "status" (a zw_status) and the outputs, which the
// Python layer (zwidth/box.py) reads only when status is ZW_OK.
namespace {

// The plant-side parts of a box (box.h: k_lo, k_hi, m_h_lo, m_h_hi, b_h_lo, b_h_hi, k_h_lo,
// k_h_hi, tau_lo, tau_hi), a sequence of 10 numbers or None (all 0: no part).
void box_set_parts(zw_plant_box &box, const py::object &parts) {
    double v[10] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    if (!parts.is_none()) {
        const py::sequence seq = py::reinterpret_borrow<py::sequence>(parts);
        if (seq.size() != 10) throw py::value_error("parts must hold 10 numbers (box.h's plant-side fields)");
        for (std::size_t i = 0; i < 10; ++i) v[i] = py::cast<double>(seq[i]);
    }
    box.k_lo = v[0];
    box.k_hi = v[1];
    box.m_h_lo = v[2];
    box.m_h_hi = v[3];
    box.b_h_lo = v[4];
    box.b_h_hi = v[5];
    box.k_h_lo = v[6];
    box.k_h_hi = v[7];
    box.tau_lo = v[8];
    box.tau_hi = v[9];
}

struct BoxCall {
    zw_plant_box box;
    std::vector<zw_box_cell> cells;
    zw_box_work work;
    BoxCall(double m_lo, double m_hi, double b_lo, double b_hi, double T, long capacity, long max_evals,
            double rel_tol)
        : box{m_lo, m_hi, b_lo, b_hi, T, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0} {
        if (capacity < static_cast<long>(ZW_BOX_MIN_CELLS) || capacity > (1L << 24))
            throw py::value_error("capacity must be in " + std::to_string(ZW_BOX_MIN_CELLS) + "..2^24");
        if (max_evals < 1 || max_evals > static_cast<long>(ZW_BOX_MAX_EVALS))
            throw py::value_error("max_evals must be in 1.." + std::to_string(ZW_BOX_MAX_EVALS));
        cells.resize(static_cast<std::size_t>(capacity));
        work.cells = cells.data();
        work.capacity = static_cast<uint_least32_t>(capacity);
        work.max_evals = static_cast<uint_least32_t>(max_evals);
        work.rel_tol = rel_tol;
    }
};

py::dict box_k_max(double m_lo, double m_hi, double b_lo, double b_hi, double T, double B, long capacity,
                   long max_evals, double rel_tol, const py::object &parts) {
    BoxCall c(m_lo, m_hi, b_lo, b_hi, T, capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    zw_box_bound r;
    zw_status st;
    {
        py::gil_scoped_release release;
        st = zw_box_k_max(&c.box, B, &c.work, &r);
    }
    py::dict out;
    out["status"] = int{st};
    out["K_lower"] = r.K_lower;
    out["K_upper"] = r.K_upper;
    out["m_worst"] = r.m_worst;
    out["b_worst"] = r.b_worst;
    out["evals"] = static_cast<long>(r.evals);
    out["converged"] = r.converged;
    out["k_worst"] = r.k_worst;
    return out;
}

py::dict box_check(double m_lo, double m_hi, double b_lo, double b_hi, double T, double K, double B, long capacity,
                   long max_evals, double rel_tol, const py::object &parts) {
    BoxCall c(m_lo, m_hi, b_lo, b_hi, T, capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    zw_box_verdict v;
    zw_status st;
    {
        py::gil_scoped_release release;
        st = zw_box_check(&c.box, K, B, &c.work, &v);
    }
    py::dict out;
    out["status"] = int{st};
    out["stable"] = v.stable;
    out["decided"] = v.decided;
    out["K_lower"] = v.K_lower;
    out["m_worst"] = v.m_worst;
    out["b_worst"] = v.b_worst;
    return out;
}

py::dict box_b_range(double m_lo, double m_hi, double b_lo, double b_hi, double T, double K, long capacity,
                     long max_evals, double rel_tol, const py::object &parts) {
    BoxCall c(m_lo, m_hi, b_lo, b_hi, T, capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    double lo = 0.0, hi = 0.0;
    bool nonempty = false;
    zw_status st;
    {
        py::gil_scoped_release release;
        st = zw_box_b_range(&c.box, K, &c.work, &lo, &hi, &nonempty);
    }
    py::dict out;
    out["status"] = int{st};
    out["B_lo"] = lo;
    out["B_hi"] = hi;
    out["nonempty"] = nonempty;
    return out;
}

py::dict box_k_mmax(double m_lo, double m_hi, double b_lo, double b_hi, double T, long capacity, long max_evals,
                    double rel_tol, const py::object &parts) {
    BoxCall c(m_lo, m_hi, b_lo, b_hi, T, capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    zw_box_extremes x;
    zw_status st;
    {
        py::gil_scoped_release release;
        st = zw_box_k_mmax(&c.box, &c.work, &x);
    }
    py::dict out;
    out["status"] = int{st};
    out["K_mmax"] = x.K_mmax;
    out["B_at"] = x.B_at;
    out["K_upper_at"] = x.K_upper_at;
    out["K_mmax_upper"] = x.K_mmax_upper;
    out["m_worst"] = x.m_worst;
    out["b_worst"] = x.b_worst;
    out["converged"] = x.converged;
    return out;
}

// ---- the general loop over a plant box (box.h, box_loop.c) --------------------------------
// The loop as the Device kernels take it: delay, differentiator, filter codes, the low-pass
// cut-off f_c [Hz] (pole_given false) or pole a (pole_given true), the average length.
struct BoxLoopCall {
    zw_plant_box box;
    zw_device_loop_spec spec{};
    std::vector<zw_box_loop_cell> cells;
    std::unique_ptr<zw_box_loop_scratch> scratch{new zw_box_loop_scratch};
    zw_box_loop_work work;
    zw_loop_workspace ws;
    BoxLoopCall(double m_lo, double m_hi, double b_lo, double b_hi, double T, unsigned delay, int differentiator,
                int filter, double cutoff_or_pole, bool pole_given, unsigned average, long capacity,
                long max_evals, double rel_tol)
        : box{m_lo, m_hi, b_lo, b_hi, T, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0} {
        if (capacity < static_cast<long>(ZW_BOX_LOOP_MIN_CELLS) || capacity > (1L << 24))
            throw py::value_error("capacity must be in " + std::to_string(ZW_BOX_LOOP_MIN_CELLS) + "..2^24");
        if (max_evals < 1 || max_evals > static_cast<long>(ZW_BOX_MAX_EVALS))
            throw py::value_error("max_evals must be in 1.." + std::to_string(ZW_BOX_MAX_EVALS));
        spec.delay = delay;
        spec.differentiator = static_cast<zw_differentiator>(differentiator);
        spec.filter = static_cast<zw_velocity_filter>(filter);
        spec.average = average;
        if (spec.filter == ZW_VFILTER_LOWPASS) {
            if (pole_given) spec.pole = cutoff_or_pole;
            else spec.cutoff_hz = cutoff_or_pole;
        }
        cells.resize(static_cast<std::size_t>(capacity));
        work.cells = cells.data();
        work.scratch = scratch.get();
        work.capacity = static_cast<uint_least32_t>(capacity);
        work.max_evals = static_cast<uint_least32_t>(max_evals);
        work.rel_tol = rel_tol;
    }
};

py::dict box_loop_k_max(double m_lo, double m_hi, double b_lo, double b_hi, double T, unsigned delay,
                        int differentiator, int filter, double cutoff_or_pole, bool pole_given, unsigned average,
                        double B, long capacity, long max_evals, double rel_tol, const py::object &parts) {
    BoxLoopCall c(m_lo, m_hi, b_lo, b_hi, T, delay, differentiator, filter, cutoff_or_pole, pole_given, average,
                  capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    zw_box_loop_bound r;
    zw_status st;
    {
        py::gil_scoped_release release;
        st = zw_box_loop_k_max(&c.box, &c.spec, &c.ws, B, &c.work, &r);
    }
    py::dict out;
    out["status"] = int{st};
    out["K_lower"] = r.K_lower;
    out["K_upper"] = r.K_upper;
    out["m_worst"] = r.m_worst;
    out["b_worst"] = r.b_worst;
    out["evals"] = static_cast<long>(r.evals);
    out["converged"] = r.converged;
    out["k_worst"] = r.k_worst;
    return out;
}

py::dict box_loop_check(double m_lo, double m_hi, double b_lo, double b_hi, double T, unsigned delay,
                        int differentiator, int filter, double cutoff_or_pole, bool pole_given, unsigned average,
                        double K, double B, long capacity, long max_evals, double rel_tol, const py::object &parts) {
    BoxLoopCall c(m_lo, m_hi, b_lo, b_hi, T, delay, differentiator, filter, cutoff_or_pole, pole_given, average,
                  capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    zw_box_loop_verdict v;
    zw_status st;
    {
        py::gil_scoped_release release;
        st = zw_box_loop_check(&c.box, &c.spec, &c.ws, K, B, &c.work, &v);
    }
    py::dict out;
    out["status"] = int{st};
    out["stable"] = v.stable;
    out["decided"] = v.decided;
    out["m_worst"] = v.m_worst;
    out["b_worst"] = v.b_worst;
    out["evals"] = static_cast<long>(v.evals);
    out["k_worst"] = v.k_worst;
    return out;
}

py::dict box_loop_b_range(double m_lo, double m_hi, double b_lo, double b_hi, double T, unsigned delay,
                          int differentiator, int filter, double cutoff_or_pole, bool pole_given, unsigned average,
                          double K, long capacity, long max_evals, double rel_tol, const py::object &parts) {
    BoxLoopCall c(m_lo, m_hi, b_lo, b_hi, T, delay, differentiator, filter, cutoff_or_pole, pole_given, average,
                  capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    double lo = 0.0, hi = 0.0;
    bool nonempty = false;
    zw_status st;
    {
        py::gil_scoped_release release;
        st = zw_box_loop_b_range(&c.box, &c.spec, &c.ws, K, &c.work, &lo, &hi, &nonempty);
    }
    py::dict out;
    out["status"] = int{st};
    out["B_lo"] = lo;
    out["B_hi"] = hi;
    out["nonempty"] = nonempty;
    return out;
}

py::dict box_loop_k_mmax(double m_lo, double m_hi, double b_lo, double b_hi, double T, unsigned delay,
                         int differentiator, int filter, double cutoff_or_pole, bool pole_given, unsigned average,
                         long capacity, long max_evals, double rel_tol, const py::object &parts) {
    BoxLoopCall c(m_lo, m_hi, b_lo, b_hi, T, delay, differentiator, filter, cutoff_or_pole, pole_given, average,
                  capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    zw_box_loop_extremes x;
    zw_status st;
    {
        py::gil_scoped_release release;
        st = zw_box_loop_k_mmax(&c.box, &c.spec, &c.ws, &c.work, &x);
    }
    py::dict out;
    out["status"] = int{st};
    out["K_mmax"] = x.K_mmax;
    out["B_at"] = x.B_at;
    out["K_upper_at"] = x.K_upper_at;
    out["m_worst"] = x.m_worst;
    out["b_worst"] = x.b_worst;
    out["evals"] = static_cast<long>(x.evals);
    out["converged"] = x.converged;
    out["k_worst"] = x.k_worst;
    return out;
}

// ---- box certificates (box_cert.h), built and verified in the drive's precision --------------
zwb_box_args cert_args(const BoxLoopCall &c, double cutoff_or_pole, bool pole_given) {
    zwb_box_args a{};
    const zw_plant_box &b = c.box;
    const double f[15] = {b.m_lo, b.m_hi, b.b_lo, b.b_hi, b.T, b.k_lo, b.k_hi, b.m_h_lo, b.m_h_hi,
                          b.b_h_lo, b.b_h_hi, b.k_h_lo, b.k_h_hi, b.tau_lo, b.tau_hi};
    for (int i = 0; i < 15; ++i) a.box[i] = f[i];
    a.delay = c.spec.delay;
    a.average = c.spec.average;
    a.differentiator = static_cast<int>(c.spec.differentiator);
    a.filter = static_cast<int>(c.spec.filter);
    a.pole_given = pole_given ? 1 : 0;
    a.cutoff_or_pole = cutoff_or_pole;
    return a;
}

py::dict cert_dict(const zw_box_cert &cert) {
    py::dict out;
    py::list B, K, nodes;
    for (unsigned i = 0; i <= cert.n_steps && i <= ZW_BOX_CERT_MAX_STEPS; ++i) B.append(double{cert.B[i]});
    for (unsigned i = 0; i < cert.n_steps && i < ZW_BOX_CERT_MAX_STEPS; ++i) K.append(double{cert.K[i]});
    for (unsigned i = 0; i < cert.n_nodes && i < ZW_BOX_CERT_MAX_NODES; ++i)
        nodes.append((cert.nodes[i / 4u] >> (4u * (i % 4u))) & 0xFu);
    out["n_steps"] = unsigned{cert.n_steps};
    out["n_nodes"] = unsigned{cert.n_nodes};
    out["B"] = B;
    out["K"] = K;
    out["nodes"] = nodes;
    return out;
}

std::vector<double> numbers_of(const py::handle &h) {
    std::vector<double> v;
    for (const py::handle &x : py::reinterpret_borrow<py::sequence>(h)) v.push_back(py::cast<double>(x));
    return v;
}

zw_box_cert cert_from(const py::dict &d) {
    zw_box_cert cert{};
    const std::vector<double> B = numbers_of(d["B"]), K = numbers_of(d["K"]), nodes = numbers_of(d["nodes"]);
    if (B.size() > ZW_BOX_CERT_MAX_STEPS + 1u || K.size() > ZW_BOX_CERT_MAX_STEPS ||
        nodes.size() > ZW_BOX_CERT_MAX_NODES)
        throw py::value_error("certificate too large for the wire format");
    cert.n_steps = static_cast<uint_least16_t>(py::cast<unsigned>(d["n_steps"]));
    cert.n_nodes = static_cast<uint_least16_t>(py::cast<unsigned>(d["n_nodes"]));
    for (std::size_t i = 0; i < B.size(); ++i) cert.B[i] = static_cast<float>(B[i]);
    for (std::size_t i = 0; i < K.size(); ++i) cert.K[i] = static_cast<float>(K[i]);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const unsigned code = static_cast<unsigned>(nodes[i]) & 0xFu;
        cert.nodes[i / 4u] = static_cast<uint_least16_t>(cert.nodes[i / 4u] | (code << (4u * (i % 4u))));
    }
    return cert;
}

py::dict box_cert_build(double m_lo, double m_hi, double b_lo, double b_hi, double T, unsigned delay,
                        int differentiator, int filter, double cutoff_or_pole, bool pole_given, unsigned average,
                        double B_lo, double B_hi, long steps, long leaves, bool single, long capacity,
                        long max_evals, double rel_tol, const py::object &parts) {
    BoxLoopCall c(m_lo, m_hi, b_lo, b_hi, T, delay, differentiator, filter, cutoff_or_pole, pole_given, average,
                  capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    if (steps < 1 || steps > static_cast<long>(ZW_BOX_CERT_MAX_STEPS))
        throw py::value_error("steps must be in 1.." + std::to_string(ZW_BOX_CERT_MAX_STEPS));
    if (leaves < steps || leaves > static_cast<long>(ZW_BOX_CERT_MAX_LEAVES))
        throw py::value_error("leaves must be in steps.." + std::to_string(ZW_BOX_CERT_MAX_LEAVES));
    const zwb_box_args a = cert_args(c, cutoff_or_pole, pole_given);
    zw_box_cert cert{};
    zwb_box_cert_result r{};
    int rc;
    {
        py::gil_scoped_release release;
        rc = (single ? zwb_box_cert_build_f : zwb_box_cert_build_d)(
            &a, static_cast<float>(B_lo), static_cast<float>(B_hi), static_cast<unsigned>(steps),
            static_cast<unsigned>(leaves), rel_tol, &cert, &r);
    }
    if (rc != 0) throw std::bad_alloc();
    py::dict out = cert_dict(cert);
    py::list upper;
    for (long i = 0; i < steps; ++i) upper.append(r.K_upper[i]);
    out["status"] = r.status;
    out["failed_step"] = r.failed_step;
    out["tests"] = r.tests;
    out["leaves"] = r.leaves;
    out["K_upper"] = upper;
    out["verify_status"] = r.verify_status;
    out["fault"] = r.fault;
    out["verify_leaves"] = r.verify_leaves;
    out["build_seconds"] = r.build_seconds;
    out["verify_seconds"] = r.verify_seconds;
    return out;
}

py::dict box_cert_verify(double m_lo, double m_hi, double b_lo, double b_hi, double T, unsigned delay,
                         int differentiator, int filter, double cutoff_or_pole, bool pole_given, unsigned average,
                         const py::dict &certificate, bool single, long capacity, long max_evals, double rel_tol,
                         const py::object &parts) {
    BoxLoopCall c(m_lo, m_hi, b_lo, b_hi, T, delay, differentiator, filter, cutoff_or_pole, pole_given, average,
                  capacity, max_evals, rel_tol);
    box_set_parts(c.box, parts);
    const zwb_box_args a = cert_args(c, cutoff_or_pole, pole_given);
    const zw_box_cert cert = cert_from(certificate);
    int fault = 0;
    unsigned long leaves = 0;
    int st;
    {
        py::gil_scoped_release release;
        st = (single ? zwb_box_cert_verify_f : zwb_box_cert_verify_d)(&a, &cert, &fault, &leaves);
    }
    if (st < 0) throw std::bad_alloc();
    py::dict out;
    out["status"] = st;
    out["fault"] = fault;
    out["leaves"] = leaves;
    return out;
}

}  // namespace

void zw_register_box(py::module_ &mod) {
    const auto ml = py::arg("m_lo"), mh = py::arg("m_hi"), bl = py::arg("b_lo"), bh = py::arg("b_hi"),
               T = py::arg("T"), cap = py::arg("capacity"), ev = py::arg("max_evals"), tol = py::arg("rel_tol");
    const auto parts = py::arg("parts") = py::none();  // box.h's plant-side fields (10) or None
    mod.def("box_k_max", &box_k_max, ml, mh, bl, bh, T, py::arg("B"), cap, ev, tol, parts, "zw_box_k_max.");
    mod.def("box_check", &box_check, ml, mh, bl, bh, T, py::arg("K"), py::arg("B"), cap, ev, tol, parts, "zw_box_check.");
    mod.def("box_b_range", &box_b_range, ml, mh, bl, bh, T, py::arg("K"), cap, ev, tol, parts, "zw_box_b_range.");
    mod.def("box_k_mmax", &box_k_mmax, ml, mh, bl, bh, T, cap, ev, tol, parts, "zw_box_k_mmax.");
    mod.attr("BOX_DEFAULT_EVALS") = long{ZW_BOX_DEFAULT_EVALS};
    mod.attr("BOX_DEFAULT_REL_TOL") = double{ZW_BOX_DEFAULT_REL_TOL};
    mod.def("box_loop_k_max", &box_loop_k_max, ml, mh, bl, bh, T, py::arg("delay"), py::arg("differentiator"),
            py::arg("filter"), py::arg("cutoff_or_pole"), py::arg("pole_given"), py::arg("average"), py::arg("B"),
            cap, ev, tol, parts, "zw_box_loop_k_max.");
    mod.def("box_loop_check", &box_loop_check, ml, mh, bl, bh, T, py::arg("delay"), py::arg("differentiator"),
            py::arg("filter"), py::arg("cutoff_or_pole"), py::arg("pole_given"), py::arg("average"), py::arg("K"),
            py::arg("B"), cap, ev, tol, parts, "zw_box_loop_check.");
    mod.def("box_loop_b_range", &box_loop_b_range, ml, mh, bl, bh, T, py::arg("delay"), py::arg("differentiator"),
            py::arg("filter"), py::arg("cutoff_or_pole"), py::arg("pole_given"), py::arg("average"), py::arg("K"),
            cap, ev, tol, parts, "zw_box_loop_b_range.");
    mod.def("box_loop_k_mmax", &box_loop_k_mmax, ml, mh, bl, bh, T, py::arg("delay"), py::arg("differentiator"),
            py::arg("filter"), py::arg("cutoff_or_pole"), py::arg("pole_given"), py::arg("average"), cap, ev, tol, parts,
            "zw_box_loop_k_mmax.");
    mod.attr("BOX_LOOP_DEFAULT_REL_TOL") = double{ZW_BOX_LOOP_DEFAULT_REL_TOL};
    mod.def("box_cert_build", &box_cert_build, ml, mh, bl, bh, T, py::arg("delay"), py::arg("differentiator"),
            py::arg("filter"), py::arg("cutoff_or_pole"), py::arg("pole_given"), py::arg("average"), py::arg("B_lo"),
            py::arg("B_hi"), py::arg("steps"), py::arg("leaves"), py::arg("single"), cap, ev, tol, parts,
            "zw_box_cert_build then zw_box_cert_verify, in float (single) or double.");
    mod.def("box_cert_verify", &box_cert_verify, ml, mh, bl, bh, T, py::arg("delay"), py::arg("differentiator"),
            py::arg("filter"), py::arg("cutoff_or_pole"), py::arg("pole_given"), py::arg("average"),
            py::arg("certificate"), py::arg("single"), cap, ev, tol, parts, "zw_box_cert_verify.");
    mod.attr("BOX_CERT_MAX_STEPS") = long{ZW_BOX_CERT_MAX_STEPS};
    mod.attr("BOX_CERT_MAX_LEAVES") = long{ZW_BOX_CERT_MAX_LEAVES};
}
