/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

// zwidth._core.Simulator, sim_judge, SIM_EFFECTS: the scene simulation of sim.h on numpy.
//
// The scene arrives as a flat dict mirroring zw_sim_scene (hand_mass for hand.mass, ...);
// the Python layer (zwidth/scene.py) builds it from a TOML file with units.  A Simulator
// owns its zw_sim and the schedule's segments (sim.h: they must outlive the run), and
// run() continues the run for n samples without the GIL, so a caller can run in chunks
// (progress bars) and other threads keep going.  No dynamics here: each sample is the C
// core's.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstddef>
#include <cstdio>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

extern "C" {
#include "zwidth/sim.h"
}

namespace py = pybind11;

namespace {

// The flat keys of the scene dict: a real field, or an int field, of zw_sim_scene.
struct RealKey {
    const char *name;
    zw_real *(*field)(zw_sim_scene &);
};

#define ZW_REAL_KEY(key, member) {key, [](zw_sim_scene &s) -> zw_real * { return &s.member; }}
const RealKey kRealKeys[] = {
    ZW_REAL_KEY("m", m), ZW_REAL_KEY("b", b), ZW_REAL_KEY("T", T), ZW_REAL_KEY("K", K), ZW_REAL_KEY("B", B),
    ZW_REAL_KEY("x_init", x_init), ZW_REAL_KEY("v_init", v_init),
    ZW_REAL_KEY("x_eq_before", x_eq_before), ZW_REAL_KEY("x_eq_after", x_eq_after),
    ZW_REAL_KEY("t_step", t_step), ZW_REAL_KEY("counts_per_unit", counts_per_unit),
    ZW_REAL_KEY("coulomb", coulomb), ZW_REAL_KEY("stiction", stiction),
    ZW_REAL_KEY("force_max", force_max), ZW_REAL_KEY("cutoff_hz", cutoff_hz),
    ZW_REAL_KEY("actuator_tau", actuator_tau),
    ZW_REAL_KEY("hand_mass", hand.mass), ZW_REAL_KEY("hand_stiffness", hand.stiffness),
    ZW_REAL_KEY("hand_damping", hand.damping), ZW_REAL_KEY("hand_t_grasp", hand.t_grasp),
    ZW_REAL_KEY("hand_t_release", hand.t_release), ZW_REAL_KEY("hand_from", hand.from),
    ZW_REAL_KEY("hand_to", hand.to), ZW_REAL_KEY("hand_speed", hand.speed),
    ZW_REAL_KEY("wall_position", wall.position), ZW_REAL_KEY("wall_stiffness", wall.stiffness),
    ZW_REAL_KEY("wall_damping", wall.damping), ZW_REAL_KEY("knob_first", knob.first),
    ZW_REAL_KEY("knob_pitch", knob.pitch), ZW_REAL_KEY("knob_k_detent", knob.k_detent),
    ZW_REAL_KEY("knob_k_end", knob.k_end), ZW_REAL_KEY("knob_damping", knob.damping),
};
#undef ZW_REAL_KEY

struct IntKey {
    const char *name;
    int *(*field)(zw_sim_scene &);
};
// substeps is int_least32_t (enforceable on a 16-bit-int target); on every host the
// bindings build for it is int, which the table below relies on.
static_assert(std::is_same<decltype(zw_sim_scene::substeps), int>::value,
              "zw_sim_scene::substeps is not int here: give it its own accessor");

const IntKey kIntKeys[] = {
    {"delay_samples", [](zw_sim_scene &s) { return &s.delay_samples; }},
    {"average_samples", [](zw_sim_scene &s) { return &s.average_samples; }},
    {"wall_side", [](zw_sim_scene &s) { return &s.wall.side; }},
    {"knob_count", [](zw_sim_scene &s) { return &s.knob.count; }},
    {"substeps", [](zw_sim_scene &s) { return &s.substeps; }},
};

// The trace fields by signal name, in sim.h's order.
struct Signal {
    const char *name;
    zw_real *zw_sim_trace::*field;
};

const Signal kSignals[] = {
    {"t", &zw_sim_trace::t},
    {"x", &zw_sim_trace::x},
    {"v", &zw_sim_trace::v},
    {"x_measured", &zw_sim_trace::x_measured},
    {"force", &zw_sim_trace::force},
    {"force_command", &zw_sim_trace::force_command},
    {"stiffness", &zw_sim_trace::stiffness},
    {"stiffness_planned", &zw_sim_trace::stiffness_planned},
    {"damping", &zw_sim_trace::damping},
    {"velocity_estimate", &zw_sim_trace::velocity_estimate},
    {"wall_force", &zw_sim_trace::wall_force},
    {"friction", &zw_sim_trace::friction},
    {"hand_force", &zw_sim_trace::hand_force},
    {"hand_target", &zw_sim_trace::hand_target},
};

std::string status_text(zw_status s) { return zw_status_name(s); }

std::string known_keys() {
    std::string out;
    for (const auto &k : kRealKeys) out += std::string(out.empty() ? "" : ", ") + k.name;
    for (const auto &k : kIntKeys) out += std::string(", ") + k.name;
    return out + ", effects, schedule";
}

std::string known_signals() {
    std::string out;
    for (const auto &s : kSignals) out += std::string(out.empty() ? "" : ", ") + s.name;
    return out;
}

// An integer-valued field: Python ints (and numpy integers) only, in int's range.
long long integer_of(const std::string &key, py::handle value) {
    if (py::isinstance<py::bool_>(value) || !py::hasattr(value, "__index__"))
        throw py::value_error("Simulator: scene['" + key + "'] must be an integer, got " +
                              std::string(py::repr(value)));
    return py::reinterpret_borrow<py::object>(value).attr("__index__")().cast<long long>();
}

class Simulator {
  public:
    // A copy of the dict, so .scene says what was simulated whatever the caller changes.
    explicit Simulator(const py::dict &scene) : scene_dict_(scene.attr("copy")()) {
        zw_sim_scene s{};
        for (auto item : scene) {
            const std::string key = py::str(item.first);
            if (set_real(s, key, item.second) || set_int(s, key, item.second)) continue;
            if (key == "effects") {
                const long long e = integer_of(key, item.second);
                if (e < 0 || e > static_cast<long long>(~0u))
                    throw py::value_error("Simulator: scene['effects'] = " + std::to_string(e) +
                                          " is not a set of effect bits");
                s.effects = static_cast<unsigned>(e);
            } else if (key == "schedule") {
                set_schedule(item.second);
            } else {
                throw py::value_error("Simulator: unknown scene key '" + key + "' (known: " + known_keys() + ")");
            }
        }
        s.schedule = schedule_.empty() ? nullptr : schedule_.data();
        s.schedule_len = schedule_.size();
        const zw_status st = zw_sim_init(&sim_, &s);
        if (st != ZW_OK)
            throw py::value_error("Simulator: zw_sim_init refused the scene [" + status_text(st) + "]");
    }

    // Continue the run for n samples; one float64 array per requested signal.
    py::dict run(py::ssize_t samples, const std::vector<std::string> &signals) {
        if (samples < 0) throw py::value_error("Simulator.run: samples must be >= 0, got " + std::to_string(samples));
        zw_sim_trace trace{};
        std::vector<std::pair<std::string, py::array_t<double>>> out;
        for (const auto &name : signals) {
            const Signal *sig = nullptr;
            for (const auto &cand : kSignals)
                if (name == cand.name) sig = &cand;
            if (sig == nullptr)
                throw py::value_error("Simulator.run: unknown signal '" + name + "' (known: " + known_signals() + ")");
            if (trace.*(sig->field) != nullptr) continue;  // asked twice: one array
            py::array_t<double> a(samples);
            trace.*(sig->field) = a.mutable_data();
            out.emplace_back(name, std::move(a));
        }
        zw_status st;
        {
            py::gil_scoped_release nogil;
            st = zw_sim_run(&sim_, static_cast<size_t>(samples), &trace);
        }
        if (st != ZW_OK) throw py::value_error("Simulator.run: zw_sim_run failed [" + status_text(st) + "]");
        py::dict result;
        for (auto &entry : out) result[py::str(entry.first)] = std::move(entry.second);
        return result;
    }

    py::ssize_t k() const { return static_cast<py::ssize_t>(sim_.k); }

    py::dict scene() const { return scene_dict_.attr("copy")(); }

    // The low-pass pole the run uses (sim.c: exp(-2 pi f_c T)), 0 without the filter: the
    // analytic verdict of a linear scene must be that of the loop actually simulated.
    double filter_pole() const { return static_cast<double>(sim_.filter_a); }

    std::string repr() const {
        char buf[160];
        std::snprintf(buf, sizeof buf, "<zwidth._core.Simulator k=%zu effects=0x%x T=%.6g>", sim_.k,
                      sim_.scene.effects, static_cast<double>(sim_.scene.T));
        return buf;
    }

  private:
    static bool set_real(zw_sim_scene &s, const std::string &key, py::handle value) {
        for (const auto &k : kRealKeys) {
            if (key != k.name) continue;
            double v;
            try {
                if (py::isinstance<py::str>(value)) throw py::cast_error();
                v = value.cast<double>();
            } catch (const py::cast_error &) {
                throw py::value_error("Simulator: scene['" + key + "'] must be a number, got " +
                                      std::string(py::repr(value)));
            }
            *k.field(s) = static_cast<zw_real>(v);
            return true;
        }
        return false;
    }

    static bool set_int(zw_sim_scene &s, const std::string &key, py::handle value) {
        for (const auto &k : kIntKeys) {
            if (key != k.name) continue;
            const long long v = integer_of(key, value);
            if (v < -2147483647LL - 1 || v > 2147483647LL)
                throw py::value_error("Simulator: scene['" + key + "'] = " + std::to_string(v) + " is out of range");
            *k.field(s) = static_cast<int>(v);
            return true;
        }
        return false;
    }

    void set_schedule(py::handle value) {
        auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
        if (!a) throw py::value_error("Simulator: scene['schedule'] must be an array of (t_start, K, B) rows");
        if (a.size() == 0) return;  // empty: no schedule
        if (a.ndim() != 2 || a.shape(1) != 3)
            throw py::value_error("Simulator: scene['schedule'] must have shape (N, 3): rows of (t_start, K, B)");
        const double *p = a.data();
        schedule_.resize(static_cast<std::size_t>(a.shape(0)));
        for (std::size_t i = 0; i < schedule_.size(); ++i)
            schedule_[i] = zw_sim_segment{static_cast<zw_real>(p[3 * i]), static_cast<zw_real>(p[3 * i + 1]),
                                          static_cast<zw_real>(p[3 * i + 2])};
    }

    py::dict scene_dict_;
    std::vector<zw_sim_segment> schedule_;  // sim_.scene.schedule points here
    zw_sim sim_{};
};

py::dict sim_judge(py::array_t<double, py::array::c_style | py::array::forcecast> x, py::ssize_t window,
                   py::ssize_t windows, double tolerance) {
    if (x.ndim() != 1) throw py::value_error("sim_judge: x must be one-dimensional");
    if (window < 0 || windows < 0) throw py::value_error("sim_judge: window and windows must be >= 0");
    zw_sim_verdict v{};
    zw_status st;
    {
        py::gil_scoped_release nogil;
        st = zw_sim_judge(x.data(), static_cast<size_t>(x.size()), static_cast<size_t>(window),
                          static_cast<size_t>(windows), static_cast<zw_real>(tolerance), &v);
    }
    if (st != ZW_OK)
        throw py::value_error("sim_judge: need window >= 1, windows >= 2, window * windows <= len(x) and a "
                              "finite tolerance >= 0 [" + status_text(st) + "]");
    static const char *const names[] = {"stable", "unstable", "undecided"};
    py::dict r;
    r["outcome"] = names[v.outcome == ZW_SIM_STABLE ? 0 : v.outcome == ZW_SIM_UNSTABLE ? 1 : 2];
    r["amplitude_first"] = static_cast<double>(v.amplitude_first);
    r["amplitude_last"] = static_cast<double>(v.amplitude_last);
    r["growth"] = static_cast<double>(v.growth);
    r["first_nonfinite"] = static_cast<py::ssize_t>(v.first_nonfinite);
    return r;
}

}  // namespace

void zw_register_sim(py::module_ &mod) {
    py::dict effects;
    effects["quantization"] = int{ZW_SIM_QUANTIZATION};
    effects["friction"] = int{ZW_SIM_FRICTION};
    effects["delay"] = int{ZW_SIM_DELAY};
    effects["saturation"] = int{ZW_SIM_SATURATION};
    effects["velocity_filter"] = int{ZW_SIM_VELOCITY_FILTER};
    effects["hand"] = int{ZW_SIM_HAND};
    effects["wall"] = int{ZW_SIM_WALL};
    effects["knob"] = int{ZW_SIM_KNOB};
    effects["schedule"] = int{ZW_SIM_SCHEDULE};
    effects["differentiator"] = int{ZW_SIM_TUSTIN};
    effects["average"] = int{ZW_SIM_AVERAGE};
    effects["actuator"] = int{ZW_SIM_ACTUATOR_LAG};
    mod.attr("SIM_EFFECTS") = effects;

    // The plain `type` metaclass (pybind11's own adds only static properties, which this
    // class has none of), so the type stub describes it exactly (mypy.stubtest).
    py::class_<Simulator>(mod, "Simulator", py::metaclass(reinterpret_cast<PyObject *>(&PyType_Type)),
                          "One run of a scene (zw_sim): Simulator(scene) validates the flat scene dict "
                          "through zw_sim_init; run(samples, signals) continues the run.")
        .def(py::init<const py::dict &>(), py::arg("scene"))
        .def("run", &Simulator::run, py::arg("samples"),
             py::arg("signals") = std::vector<std::string>{"t", "x"},
             "Advance `samples` samples; returns {signal: float64 array} (zw_sim_trace fields).")
        .def_property_readonly("k", &Simulator::k, "Samples simulated so far.")
        .def_property_readonly("scene", &Simulator::scene, "The scene dict given (a copy).")
        .def_property_readonly("filter_pole", &Simulator::filter_pole,
                               "The velocity low-pass pole a of the run (0 without the filter).")
        .def("__repr__", &Simulator::repr);

    mod.def("sim_judge", &sim_judge, py::arg("x"), py::arg("window"), py::arg("windows"), py::arg("tolerance"),
            "zw_sim_judge: the simulated verdict of a position record.");
}
