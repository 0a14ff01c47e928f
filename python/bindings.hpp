// hbfriction._core — internal to python/: what the binding files share: the system as Python
// sees it (PySystem), the conversions between Python objects and the library's types, the
// results as dicts, and the three binding functions module.cpp calls.
#pragma once

#include <pybind11/pybind11.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <limits>
#include <string>
#include <vector>

#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/diagnostics.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/exact_branch.hpp"
#include "hbf/frf.hpp"
#include "hbf/modal_exact.hpp"
#include "hbf/interface.hpp"
#include "hbf/memory.hpp"
#include "hbf/modes.hpp"
#include "hbf/optimize.hpp"
#include "hbf/output_file.hpp"
#include "hbf/reduction.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/table.hpp"
#include "hbf/time_integration.hpp"
#include "hbf/timeint_sweep.hpp"
#include "hbf/tracking.hpp"

namespace py = pybind11;

namespace hbf::python {

// ---- the system as Python sees it -----------------------------------------------------------

/// A System with what a Python caller does not pass with every call: the reported outputs
/// (empty: every DOF) and a TOML file's [frequency] and [solver] (io::SystemConfig), and the
/// preset's parameters (the JSON summary's).
struct PySystem : io::SystemConfig {
    std::optional<AbsorberParameters> absorber;  ///< the paper's preset
    std::string source;                          ///< "absorber", a file's path, or "" (arrays)

    /// The reported outputs: the chosen ones, else every DOF.
    std::vector<Output> reported() const {
        if (!outputs.empty()) return outputs;
        std::vector<Output> all;
        for (int i = 0; i < system.dofs(); ++i) all.push_back(Output::dof(i));
        return all;
    }
    /// The law, or the contacts' laws joined by ',' ("none" without contacts).
    std::string law_name() const {
        std::string name;
        for (const Contact& c : system.contacts) {
            const std::string law = to_string(c.law);
            if (("," + name + ",").find("," + law + ",") == std::string::npos) name += (name.empty() ? "" : ",") + law;
        }
        return name.empty() ? "none" : name;
    }
};

[[noreturn]] void bad(const std::string& message);


/// A 1-D or 2-D float64 array from any Python object (NumPy's asarray), through the buffer
/// protocol. `name` names the parameter in errors.
py::buffer_info float_buffer(const py::handle& value, const std::string& name);

Eigen::VectorXd to_vector(const py::handle& value, const std::string& name);

/// A square matrix from SciPy sparse (any format: its COO triplets), a dense 2-D array, or a
/// 1-D array (the diagonal, as in a TOML file). Entries must be finite; duplicates add up.
SparseMatrix to_sparse(const py::handle& value, const std::string& name);

/// A sparse matrix back to Python: scipy.sparse.csc_matrix, or a dense NumPy array where SciPy
/// is not installed.
py::object from_sparse(const SparseMatrix& m);

std::vector<double> to_list(const Eigen::VectorXd& v);

/// A 2-D array as a matrix (a 1-D array: one row), finite entries.
Eigen::MatrixXd to_rows(const py::handle& value, const std::string& name);

/// Each node's DOFs (0-based): an n x d array of whole numbers (a 1-D array: one node).
std::vector<std::vector<int>> to_nodes(const py::handle& value, const std::string& name);

py::dict interface_dict(const InterfaceContacts& f);

/// A list of Contact objects; TypeError naming `name` (and the item) for anything else.
std::vector<Contact> to_contacts(const py::handle& value, const std::string& name);

/// An int argument: a Python integer (not a bool) within C's int; TypeError / ValueError
/// naming `name` otherwise.
int to_int(const py::handle& value, const std::string& name);

/// A row-major flat copy and the shape of a matrix (NumPy reshapes it).
py::tuple matrix(const Eigen::MatrixXd& m);

// ---- tables ---------------------------------------------------------------------------------

/// A table column by column: (name, meaning, type, values); numbers with None for empty cells.
py::list table_columns(const io::Table& table);

/// A computed FRF with its table, summary and verdict (what hbf frf writes), kept for the
/// Branch object (its CSV).
struct FrfRun {
    FrfResult result;
    io::Table table;
    std::string summary;  ///< the JSON summary of hbf frf --summary
    Verdict verdict;  ///< the result's (compute_frf: FrfResult::verdict)
};

/// The table, verdict and JSON summary of a computed FRF (run->result), as hbf frf writes
/// them. `hb` (the solver that ran, or one built alike) supplies the summary's solver
/// parameters; without it (an FRF that could not start) the summary holds the status only.
void finish_run(FrfRun& run, const PySystem& s, const FrfSettings& settings, const HarmonicBalance* hb);

/// compute_frf and everything hbf frf derives from it; called without the GIL.
std::shared_ptr<FrfRun> run_frf(const PySystem& s, FrfSettings settings);

/// Runs `work` with the GIL released; a C++ exception passes through (pybind11 translates it
/// once the GIL is back).
template <class F>
auto without_gil(F&& work) {
    py::gil_scoped_release release;
    return work();
}

/// A Python callable p -> System as the library's std::function, called from worker threads
/// with the GIL re-acquired. Its ValueError becomes InvalidInput (that FRF fails, the search
/// goes on, as for an out-of-range parameter in hbf optimize); any other exception stops it.
std::function<System(double)> system_of(const py::function& f);

py::dict peak_dict(const PeakValue& p);

py::list peaks_list(const std::vector<Peak>& peaks);

py::dict optimize_dict(const OptimizeResult& r);

/// A tracking result (tracking.hpp) as plain Python values: per curve its points as lists.
py::dict track_dict(const TrackResult& r);

/// An enum field as its name: the library's to_string and parser (one table per enum, in the
/// library), whose InvalidInput names the allowed values.
template <class Class, class Struct, class T>
void enum_property(Class& cls, const char* name, T Struct::*member, T (*parse)(const std::string&), const char* doc) {
    cls.def_property(
        name, [member](const Struct& s) { return to_string(s.*member); },
        [member, parse](Struct& s, const std::string& v) { s.*member = parse(v); }, doc);
}

/// The bindings, by part: the model (System, Contact, Output, the preset, interfaces, reduction),
/// the options structs with their C++ names and defaults, and the computations.
void bind_model(py::module_& m);
void bind_options(py::module_& m);
void bind_studies(py::module_& m);

}  // namespace hbf::python
