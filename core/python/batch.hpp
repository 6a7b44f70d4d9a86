#pragma once

// Batches: one compiled call for many min_force wrenches (or growth-distance poses) on one set,
// split over threads.
//
// Each row is answered by the same function as a single call (shoot_and_read_forces,
// growth_query), on a fresh copy of the set's program, so a row's answer is bit for bit the
// single call's and does not depend on the other rows, on their order or on the thread count.
// Rows are handed out in blocks from an atomic counter: the rows' costs differ (an infeasible
// wrench stops early, a wrench near W's boundary takes more steps), and static halves would
// leave one core idle at the end.

#include <algorithm>
#include <atomic>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

#include "grasping/forces.hpp"
#include "growth/growth.hpp"

namespace gf {

namespace batch {

// a min_force row's status (graspforce.batch.STATUSES names them, in this order)
constexpr Int OPTIMAL = 0;
constexpr Int INFEASIBLE = 1;
constexpr Int MAX_ITER = 2;
constexpr Int BAD_WRENCH = 3;   // an entry is NaN or inf, or its squared norm overflows
// not a status of a batch's answer: a row left to the full-dimensional set (forces.hpp's
// FULL_SET), which graspforce.batch answers again there
constexpr Int FULL_SET = 4;

// rows a worker takes at a time: large enough that the counter is not contended, small enough
// that the last blocks balance the threads
constexpr Int BLOCK = 64;

}  // namespace batch

namespace batch_detail {

// A set's program, copied afresh for every row: the support kernel writes its work into the
// program's arrays, and a single call starts from the caller's untouched arrays.
struct ProgramCopy {
    std::vector<Int> ints;
    std::vector<double> floats;
    IVec src_ints;
    Vec src_floats;
    ProgramCopy(IVec i, Vec f) : ints(i.n), floats(f.n), src_ints(i), src_floats(f) {}
    void refresh() {
        std::memcpy(ints.data(), src_ints.d, sizeof(Int) * src_ints.n);
        std::memcpy(floats.data(), src_floats.d, sizeof(double) * src_floats.n);
    }
    IVec i() { return {ints.data(), static_cast<Int>(ints.size())}; }
    Vec f() { return {floats.data(), static_cast<Int>(floats.size())}; }
};

// Runs row(worker_state, i) for i in [0, rows) on `threads` threads (the calling one among
// them); make_state() builds a worker's buffers. The first exception of any worker stops the
// others and is rethrown here, after every thread has joined.
template <class MakeState, class Row>
void parallel_rows(Int rows, Int threads, MakeState make_state, Row row) {
    const Int blocks = (rows + batch::BLOCK - 1) / batch::BLOCK;
    if (threads < 1) threads = std::max<Int>(1, std::thread::hardware_concurrency());
    threads = std::max<Int>(1, std::min(threads, blocks));
    std::atomic<Int> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    std::mutex error_lock;
    auto work = [&]() {
        try {
            auto state = make_state();
            for (;;) {
                const Int b = next.fetch_add(1);
                if (b >= blocks || failed.load()) break;
                const Int end = std::min(rows, (b + 1) * batch::BLOCK);
                for (Int i = b * batch::BLOCK; i < end; ++i) row(state, i);
            }
        } catch (...) {
            std::lock_guard<std::mutex> hold(error_lock);
            if (!error) error = std::current_exception();
            failed = true;
        }
    };
    std::vector<std::thread> pool;
    for (Int k = 1; k < threads; ++k) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace batch_detail

// min_force for each row of `wrenches` (N, 6) on one wrench space, the arguments after them as
// Grasp.min_force passes them to shoot_and_read_forces (graspforce/grasping/grasp.py). Writes per
// row sigma, sigma_lower, status (batch::*) and iterations, and with forces.n > 0 the (m, 4) local
// forces at forces[4 m i:]; with Grasp.min_force's reading of the head: a zero wrench is
// OPTIMAL with sigma 0; a miss (which includes a ray leaving W at the origin) INFEASIBLE with
// sigma inf; a shot stopped by max_iter, or whose forces lack their certificate (forces.hpp),
// MAX_ITER, with its forces when they are finite; a row without an answer in a projected set's
// span FULL_SET, with sigma NaN; t_scale is the shot set's (m on W_Linf's lift). Rows without
// forces get zeros.
inline void min_force_rows(Mat wrenches, Int method, double eps, Int max_iter, Int packed_size,
                           Vec start, IVec ints, Vec floats, Vec reader, Vec span, double t_scale,
                           Vec sigma, Vec sigma_lower, IVec status, IVec iterations, Vec forces,
                           Int threads) {
    const Int m = static_cast<Int>(reader[3]);
    const bool with_forces = forces.n > 0;
    struct State {
        batch_detail::ProgramCopy prog;
        std::vector<double> packed;
    };
    batch_detail::parallel_rows(
        wrenches.rows, threads,
        [&]() { return State{batch_detail::ProgramCopy(ints, floats),
                             std::vector<double>(packed_size)}; },
        [&](State& s, Int i) {
            s.prog.refresh();
            const Vec packed{s.packed.data(), packed_size};
            const Head head = shoot_and_read_forces(wrenches.row(i), method, eps, max_iter,
                                                    packed, start, s.prog.i(), s.prog.f(),
                                                    reader, span);
            Int code;
            double sig, lower;
            bool read = false;
            if (head.status == BAD_WRENCH || head.status == FULL_SET) {
                code = head.status == BAD_WRENCH ? batch::BAD_WRENCH : batch::FULL_SET;
                sig = lower = std::numeric_limits<double>::quiet_NaN();
            } else if (head.status == ZERO_WRENCH) {
                code = batch::OPTIMAL;
                sig = lower = 0.0;
            } else {
                sig = packed[0];
                if (head.status == MISS) {
                    code = batch::INFEASIBLE;
                    lower = INF;
                } else if (sig == INF) {
                    code = batch::MAX_ITER;
                    lower = head.t_up > 0.0 ? 1.0 / (t_scale * head.t_up) : 0.0;
                } else {
                    code = head.status == HIT ? batch::OPTIMAL : batch::MAX_ITER;
                    lower = 1.0 / (t_scale * head.t_up);
                    read = true;
                }
            }
            sigma[i] = sig;
            sigma_lower[i] = lower;
            status[i] = code;
            iterations[i] = (head.status == BAD_WRENCH || head.status == ZERO_WRENCH ||
                             head.status == FULL_SET) ? 0 : head.iters;
            if (with_forces)
                for (Int a = 0; a < 4 * m; ++a) forces[4 * m * i + a] = read ? packed[1 + a] : 0.0;
        });
}

// growth_query for each row of the poses (R_a (N, 9) row-major, p_a (N, 3), R_b, p_b) on one
// pair's program (graspforce.GrowthDistance's, without warm start, so that a row's answer
// depends on its poses only). Writes per row the query's code, verdict, sigma, its bracket and
// iterations; packed_size: FRAME + capacity(3, ws), a worker's scratch for the query's frame.
inline void growth_rows(Mat R_a, Mat p_a, Mat R_b, Mat p_b, IVec ints, Vec floats,
                        Int packed_size, IVec code, IVec verdict, Vec sigma, Vec lower, Vec upper,
                        IVec iterations, Int threads) {
    struct State {
        batch_detail::ProgramCopy prog;
        std::vector<double> packed;
    };
    batch_detail::parallel_rows(
        R_a.rows, threads,
        [&]() { return State{batch_detail::ProgramCopy(ints, floats),
                             std::vector<double>(packed_size)}; },
        [&](State& s, Int i) {
            s.prog.refresh();
            const Mat Ra{R_a.d + 9 * i, 3, 3, 3}, Rb{R_b.d + 9 * i, 3, 3, 3};
            const GrowthOut g = growth_query(s.prog.i(), s.prog.f(), Ra, p_a.row(i), Rb,
                                             p_b.row(i), Vec{s.packed.data(), packed_size});
            code[i] = g.code;
            verdict[i] = g.verdict;
            sigma[i] = g.sigma;
            lower[i] = g.lower;
            upper[i] = g.upper;
            iterations[i] = g.iterations;
        });
}

}  // namespace gf
