// hbfriction._core — the conversions between Python objects and the library's types, and the
// results as dicts (bindings.hpp).
#include "bindings.hpp"

namespace hbf::python {

[[noreturn]] void bad(const std::string& message) { throw InvalidInput(message); }

py::buffer_info float_buffer(const py::handle& value, const std::string& name) {
    py::object numpy = py::module_::import("numpy");
    py::object array;
    try {
        array = numpy.attr("ascontiguousarray")(value, py::arg("dtype") = "float64");
    } catch (py::error_already_set& e) {
        bad(name + ": not an array of numbers (" + std::string(e.what()) + ")");
    }
    return py::buffer(array).request();
}

Eigen::VectorXd to_vector(const py::handle& value, const std::string& name) {
    const py::buffer_info b = float_buffer(value, name);
    if (b.ndim != 1 && !(b.ndim == 2 && (b.shape[0] == 1 || b.shape[1] == 1)))
        bad(name + ": a vector is required (got " + std::to_string(b.ndim) + " dimensions)");
    const auto n = static_cast<Eigen::Index>(b.size);
    Eigen::VectorXd v(n);
    const auto* data = static_cast<const double*>(b.ptr);
    for (Eigen::Index i = 0; i < n; ++i) {
        v(i) = data[i];
        if (!std::isfinite(v(i))) bad(name + "[" + std::to_string(i) + "] = " + format_number(v(i)) + " is not finite");
    }
    return v;
}

SparseMatrix to_sparse(const py::handle& value, const std::string& name) {
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::Index rows = 0, cols = 0;
    if (py::hasattr(value, "tocoo")) {
        py::buffer_info r, c, d;
        try {
            py::object coo = value.attr("tocoo")();
            py::tuple shape = coo.attr("shape");
            rows = shape[0].cast<Eigen::Index>();
            cols = shape[1].cast<Eigen::Index>();
            py::object numpy = py::module_::import("numpy");
            r = py::buffer(numpy.attr("ascontiguousarray")(coo.attr("row"), "int64")).request();
            c = py::buffer(numpy.attr("ascontiguousarray")(coo.attr("col"), "int64")).request();
            d = py::buffer(numpy.attr("ascontiguousarray")(coo.attr("data"), "float64")).request();
        } catch (py::error_already_set& e) {
            bad(name + ": not a usable sparse matrix (its tocoo() failed: " + std::string(e.what()) + ")");
        } catch (py::cast_error& e) {
            bad(name + ": not a usable sparse matrix (" + std::string(e.what()) + ")");
        }
        if (r.size != d.size || c.size != d.size) bad(name + ": the sparse matrix's row, col and data differ in length");
        const auto* ri = static_cast<const long long*>(r.ptr);
        const auto* ci = static_cast<const long long*>(c.ptr);
        const auto* di = static_cast<const double*>(d.ptr);
        if (rows < 0 || cols < 0 || rows > 50000000 || cols > 50000000)
            bad(name + ": shape " + std::to_string(rows) + " x " + std::to_string(cols) + " is out of range");
        for (py::ssize_t k = 0; k < d.size; ++k) {
            if (ri[k] < 0 || ri[k] >= rows || ci[k] < 0 || ci[k] >= cols)
                bad(name + ": entry (" + std::to_string(ri[k]) + ", " + std::to_string(ci[k]) + ") lies outside its shape");
            if (!std::isfinite(di[k]))
                bad(name + "[" + std::to_string(ri[k]) + ", " + std::to_string(ci[k]) + "] = " + format_number(di[k]) +
                    " is not finite");
            entries.emplace_back(static_cast<int>(ri[k]), static_cast<int>(ci[k]), di[k]);
        }
    } else {
        const py::buffer_info b = float_buffer(value, name);
        const auto* data = static_cast<const double*>(b.ptr);
        if (b.ndim == 1) {
            rows = cols = static_cast<Eigen::Index>(b.shape[0]);
            for (Eigen::Index i = 0; i < rows; ++i) {
                if (!std::isfinite(data[i]))
                    bad(name + "[" + std::to_string(i) + "] = " + format_number(data[i]) + " is not finite");
                if (data[i] != 0.0) entries.emplace_back(static_cast<int>(i), static_cast<int>(i), data[i]);
            }
        } else if (b.ndim == 2) {
            rows = static_cast<Eigen::Index>(b.shape[0]);
            cols = static_cast<Eigen::Index>(b.shape[1]);
            for (Eigen::Index i = 0; i < rows; ++i)
                for (Eigen::Index j = 0; j < cols; ++j) {
                    const double x = data[i * cols + j];
                    if (!std::isfinite(x))
                        bad(name + "[" + std::to_string(i) + ", " + std::to_string(j) + "] = " + format_number(x) +
                            " is not finite");
                    if (x != 0.0) entries.emplace_back(static_cast<int>(i), static_cast<int>(j), x);
                }
        } else {
            bad(name + ": a matrix is required (2-D, SciPy sparse, or 1-D for a diagonal), got " +
                std::to_string(b.ndim) + " dimensions");
        }
    }
    if (rows != cols) bad(name + ": a square matrix is required, got " + std::to_string(rows) + " x " + std::to_string(cols));
    if (rows == 0) bad(name + ": an empty matrix: at least 1 DOF is required");
    if (rows > 50000000) bad(name + ": " + std::to_string(rows) + " DOFs is out of range: allowed 1..50000000");
    SparseMatrix m(rows, cols);
    m.setFromTriplets(entries.begin(), entries.end());
    m.prune(0.0);
    m.makeCompressed();
    return m;
}

py::object from_sparse(const SparseMatrix& m) {
    py::object numpy = py::module_::import("numpy");
    std::vector<double> data(m.valuePtr(), m.valuePtr() + m.nonZeros());
    std::vector<long long> indices(m.innerIndexPtr(), m.innerIndexPtr() + m.nonZeros());
    std::vector<long long> indptr(m.outerIndexPtr(), m.outerIndexPtr() + m.outerSize() + 1);
    try {
        py::object sparse = py::module_::import("scipy.sparse");
        return sparse.attr("csc_matrix")(py::make_tuple(numpy.attr("asarray")(data, "float64"),
                                                        numpy.attr("asarray")(indices, "int64"),
                                                        numpy.attr("asarray")(indptr, "int64")),
                                         py::arg("shape") = py::make_tuple(m.rows(), m.cols()));
    } catch (py::error_already_set& e) {
        if (!e.matches(PyExc_ImportError)) throw;
    }
    const Eigen::MatrixXd dense(m);
    std::vector<double> rowmajor(static_cast<std::size_t>(dense.size()));
    for (Eigen::Index i = 0; i < dense.rows(); ++i)
        for (Eigen::Index j = 0; j < dense.cols(); ++j) rowmajor[static_cast<std::size_t>(i * dense.cols() + j)] = dense(i, j);
    return numpy.attr("asarray")(rowmajor, "float64").attr("reshape")(m.rows(), m.cols());
}

std::vector<double> to_list(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

Eigen::MatrixXd to_rows(const py::handle& value, const std::string& name) {
    const py::buffer_info b = float_buffer(value, name);
    if (b.ndim != 1 && b.ndim != 2) bad(name + ": a 1-D or 2-D array is required (got " + std::to_string(b.ndim) + " dimensions)");
    const auto rows = static_cast<Eigen::Index>(b.ndim == 2 ? b.shape[0] : 1);
    const auto cols = static_cast<Eigen::Index>(b.ndim == 2 ? b.shape[1] : b.shape[0]);
    Eigen::MatrixXd m(rows, cols);
    const auto* data = static_cast<const double*>(b.ptr);  // C order (ascontiguousarray)
    for (Eigen::Index i = 0; i < rows; ++i)
        for (Eigen::Index j = 0; j < cols; ++j) {
            m(i, j) = data[i * cols + j];
            if (!std::isfinite(m(i, j)))
                bad(name + "[" + std::to_string(i) + ", " + std::to_string(j) + "] = " + format_number(m(i, j)) + " is not finite");
        }
    return m;
}

std::vector<std::vector<int>> to_nodes(const py::handle& value, const std::string& name) {
    const Eigen::MatrixXd m = to_rows(value, name);
    std::vector<std::vector<int>> nodes(static_cast<std::size_t>(m.rows()));
    for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index j = 0; j < m.cols(); ++j) {
            const double v = m(i, j);
            if (v != std::floor(v) || std::abs(v) > 2e9)
                bad(name + "[" + std::to_string(i) + ", " + std::to_string(j) + "] = " + format_number(v) +
                    " is not a DOF index: allowed whole numbers (0-based)");
            nodes[static_cast<std::size_t>(i)].push_back(static_cast<int>(v));
        }
    return nodes;
}

py::dict interface_dict(const InterfaceContacts& f) {
    py::dict d;
    d["name"] = f.name;
    d["first"] = f.first;
    d["count"] = f.count;
    d["dimension"] = f.dimension;
    return d;
}

std::vector<Contact> to_contacts(const py::handle& value, const std::string& name) {
    if (value.is_none()) return {};
    if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) || !py::isinstance<py::sequence>(value))
        throw py::type_error(name + ": expected a list of hbfriction.Contact, got " +
                             std::string(py::str(value.get_type().attr("__name__"))));
    std::vector<Contact> contacts;
    std::size_t k = 0;
    for (const py::handle item : py::reinterpret_borrow<py::sequence>(value)) {
        if (!py::isinstance<Contact>(item))
            throw py::type_error(name + "[" + std::to_string(k) + "] = " + std::string(py::repr(item)) +
                                 ": expected an hbfriction.Contact");
        contacts.push_back(item.cast<Contact>());
        ++k;
    }
    return contacts;
}

int to_int(const py::handle& value, const std::string& name) {
    if (py::isinstance<py::bool_>(value) || !py::hasattr(value, "__index__") || py::isinstance<py::float_>(value))
        throw py::type_error(name + " = " + std::string(py::repr(value)) + ": expected an integer");
    const py::int_ whole = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
    if (!whole) throw py::error_already_set();
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(whole.ptr(), &overflow);
    if (overflow != 0 || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
        throw py::value_error(name + " = " + std::string(py::repr(value)) + " is out of the range of integers");
    return static_cast<int>(v);
}

py::tuple matrix(const Eigen::MatrixXd& m) {
    std::vector<double> flat(static_cast<std::size_t>(m.size()));
    for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index j = 0; j < m.cols(); ++j) flat[static_cast<std::size_t>(i * m.cols() + j)] = m(i, j);
    return py::make_tuple(flat, py::make_tuple(m.rows(), m.cols()));
}

py::list table_columns(const io::Table& table) {
    py::list out;
    for (std::size_t j = 0; j < table.columns.size(); ++j) {
        const io::Column& c = table.columns[j];
        py::list values;
        if (j < table.cells.size())  // a table with no rows may hold no cell lists
            for (const io::Cell& cell : table.cells[j]) {
                if (const auto* d = std::get_if<double>(&cell)) values.append(*d);
                else if (const auto* i = std::get_if<long long>(&cell)) values.append(*i);
                else if (const auto* t = std::get_if<std::string>(&cell)) values.append(*t);
                else values.append(py::none());
            }
        const char* type = c.type == io::ColumnType::text ? "text" : c.type == io::ColumnType::integer ? "integer" : "number";
        out.append(py::make_tuple(c.name, c.meaning, type, values));
    }
    return out;
}

void finish_run(FrfRun& run, const PySystem& s, const FrfSettings& settings, const HarmonicBalance* hb) {
    const FrfResult& r = run.result;
    run.verdict = r.verdict;
    const BranchStability* stability = r.stability ? &*r.stability : nullptr;
    run.table = io::frf_table(r.points, r.metrics, settings.outputs, r.exact, stability, s.interfaces);
    if (hb == nullptr) {
        run.summary = nlohmann::json{{"status", to_string(r.branch.status)}, {"message", r.branch.message}}.dump();
        return;
    }
    std::size_t samples = 0;
    for (const SolutionPoint& p : r.points) samples += p.kind == PointKind::sample ? 1 : 0;
    std::ostringstream json;
    const auto parameters = io::frf_parameters(s.system, s.absorber ? &*s.absorber : nullptr, *hb, settings.continuation);
    io::write_frf_summary(json, s.law_name(), parameters, r.branch, r.metrics, r.peaks, samples, r.seconds,
                          settings.outputs, r.polish ? &*r.polish : nullptr, run.verdict.errors, run.verdict.warnings,
                          run.verdict.notes, stability);
    run.summary = json.str();
}

std::shared_ptr<FrfRun> run_frf(const PySystem& s, FrfSettings settings) {
    if (settings.outputs.empty()) settings.outputs = s.reported();
    auto run = std::make_shared<FrfRun>();
    settings.validate();
    HarmonicBalance hb(s.system, settings.harmonic_balance);
    run->result = compute_frf(hb, settings);
    finish_run(*run, s, settings, &hb);
    return run;
}

std::function<System(double)> system_of(const py::function& f) {
    return [f](double p) -> System {
        py::gil_scoped_acquire gil;
        try {
            py::object result = f(p);
            return result.cast<const PySystem&>().system;
        } catch (py::error_already_set& e) {
            if (e.matches(PyExc_ValueError)) throw InvalidInput(e.what());
            throw std::runtime_error("the system function raised at p = " + format_number(p) + ": " + e.what());
        } catch (py::cast_error&) {
            throw std::runtime_error("the system function must return an hbfriction.System (at p = " +
                                     format_number(p) + ")");
        }
    };
}

py::dict peak_dict(const PeakValue& p) {
    py::dict d;
    d["value"] = p.value;
    d["w"] = p.omega;
    d["state"] = to_string(p.state);
    return d;
}

py::list peaks_list(const std::vector<Peak>& peaks) {
    py::list out;
    for (const Peak& p : peaks) {
        py::dict d;
        d["w"] = p.omega;
        d["y_max"] = p.y_max;
        d["branch"] = p.branch;
        d["refined"] = p.refined;
        d["output"] = p.output;
        out.append(d);
    }
    return out;
}

py::dict optimize_dict(const OptimizeResult& r) {
    py::dict d;
    d["status"] = to_string(r.status);
    d["parameter"] = r.parameter;
    d["peak"] = peak_dict(r.peak);
    d["peaks"] = peaks_list(r.peaks);
    d["bracket"] = py::make_tuple(r.bracket_lower, r.bracket_upper);
    py::list trace;
    for (const OptimizeEvaluation& e : r.trace) {
        py::dict t;
        t["parameter"] = e.parameter;
        t["peak"] = e.peak.value;
        t["w"] = e.peak.omega;
        t["state"] = to_string(e.peak.state);
        t["status"] = to_string(e.status);
        t["phase"] = e.phase;
        t["seconds"] = e.seconds;
        trace.append(t);
    }
    d["trace"] = trace;
    d["failed"] = r.failed;
    d["failed_in_bracket"] = r.failed_in_bracket;
    d["message"] = r.message;
    d["seconds"] = r.seconds;
    d["summary"] = r.summary();
    const Verdict v = r.verdict();  // the library's (frf.hpp), as hbf optimize's exit code
    d["outcome"] = v.status();
    d["errors"] = v.errors;
    d["warnings"] = v.warnings;
    d["notes"] = v.notes;
    return d;
}

py::dict track_dict(const TrackResult& r) {
    py::dict d;
    d["feature"] = to_string(r.feature);
    d["exact"] = r.exact;
    d["harmonics"] = r.harmonics;
    py::list curves;
    for (const TrackCurve& c : r.curves) {
        py::dict cd;
        cd["id"] = c.id;
        cd["label"] = c.label;
        cd["status"] = to_string(c.status);
        cd["message"] = c.message;
        cd["contact"] = c.contact;
        cd["boundary"] = to_string(c.boundary);
        std::vector<double> p, w, value, curvature;
        std::vector<std::string> kind, regime;
        std::vector<bool> corner;
        for (const TrackPoint& q : c.points) {
            p.push_back(q.p);
            w.push_back(q.omega);
            value.push_back(q.value);
            curvature.push_back(q.curvature);
            kind.push_back(q.kind);
            regime.push_back(q.regime);
            corner.push_back(q.corner);
        }
        cd["p"] = p;
        cd["w"] = w;
        cd["value"] = value;
        cd["curvature"] = curvature;
        cd["kind"] = kind;
        cd["regime"] = regime;
        cd["corner"] = corner;
        curves.append(cd);
    }
    d["curves"] = curves;
    py::list events;
    for (const TrackEvent& e : r.events) {
        py::dict ed;
        ed["kind"] = e.kind;
        ed["p"] = e.p;
        ed["w"] = e.omega;
        ed["value"] = e.value;
        ed["curve"] = e.curve;
        ed["other"] = e.other;
        ed["other_w"] = e.other_omega;
        events.append(ed);
    }
    d["events"] = events;
    d["solves"] = r.solves;
    d["frfs"] = r.frfs;
    d["seconds"] = r.seconds;
    d["summary"] = r.summary();
    d["outcome"] = r.verdict.status();
    d["errors"] = r.verdict.errors;
    d["warnings"] = r.verdict.warnings;
    d["notes"] = r.verdict.notes;
    return d;
}

}  // namespace hbf::python
