// hbfriction._core — the model as Python sees it: Output, Contact, the preset, System, interfaces
// and reduction (bindings.hpp).
#include "bindings.hpp"

namespace hbf::python {

void bind_model(py::module_& m) {
    // ---- model ----------------------------------------------------------------------------
    py::class_<Output>(m, "Output", "A reported response o(t) = c^T y(t): one DOF or a combination of DOFs")
        .def(py::init([](const std::string& name, const std::vector<std::pair<int, double>>& terms) {
                 if (name.empty()) bad("Output name: empty, allowed a non-empty name");
                 return Output(name, terms);
             }),
             py::arg("name"), py::arg("terms"), "name and (0-based DOF, coefficient) pairs")
        .def_static(
            "dof",
            [](int i) {
                if (i < 0) bad("Output.dof: i = " + std::to_string(i) + " is out of range: allowed a DOF >= 0 (0-based)");
                return Output::dof(i);
            },
            py::arg("i"), "DOF i (0-based), named y<i+1>")
        .def_property_readonly("name", &Output::name)
        .def_property_readonly("terms", &Output::terms)
        .def("__repr__", [](const Output& o) { return "Output('" + o.name() + "', " + std::to_string(o.terms().size()) + " term(s))"; });

    py::class_<Contact> contact(m, "Contact", "One friction contact (model.hpp; DOFs 0-based)");
    contact.def(py::init<>())
        .def_readonly_static("ground", &Contact::ground)
        .def_readwrite("dof", &Contact::dof, "DOF a (0-based)")
        .def_readwrite("other_dof", &Contact::other_dof, "DOF b (0-based), or Contact.ground (-1)")
        .def_property(
            "direction", [](const Contact& c) { return to_list(c.direction); },
            [](Contact& c, const py::object& v) {
                c.direction = v.is_none() ? Eigen::VectorXd() : to_vector(v, "direction");
            },
            "w_c, the force direction (N numbers; empty: dof/other_dof)")
        .def_property(
            "law", [](const Contact& c) { return to_string(c.law); },
            [](Contact& c, const std::string& v) { c.law = parse_friction_law(v); },
            contact_law_names().c_str())
        .def_readwrite("friction_limit", &Contact::friction_limit, "F_c = mu N (> 0)")
        ;
    // The laws' parameters, from the registry (contact_law.hpp): one property a key, documented by
    // what it is in each law that has it.
    {
        std::vector<std::string> keys;
        std::map<std::string, std::string> docs;
        std::map<std::string, LawParameter> parameters;
        for (const ContactLaw* law : contact_laws())
            for (const LawParameter& p : law->parameters()) {
                if (!parameters.count(p.key)) keys.emplace_back(p.key);
                parameters.insert_or_assign(p.key, p);
                const std::string range = p.kind == LawParameter::Kind::pairs       ? "a list of pairs (a, b)"
                                          : p.kind == LawParameter::Kind::direction      ? "N numbers, one per DOF"
                                          : p.kind == LawParameter::Kind::direction_rows ? "rows of N numbers"
                                          : p.kind == LawParameter::Kind::rows           ? "rows of equal length"
                                                                                         : p.allowed();
                std::string& doc = docs[p.key];
                doc += (doc.empty() ? "" : "; ") + std::string(p.meaning) + " (" + law->name() + ", " + range +
                       (p.zero_means ? std::string("; 0: ") + p.zero_means : std::string()) + ")";
            }
        for (const std::string& key : keys) {
            const LawParameter p = parameters.at(key);
            if (p.kind == LawParameter::Kind::pairs) {
                contact.def_property(
                    key.c_str(),
                    [key](const Contact& c) {
                        py::list rows;
                        const auto at = c.lists.find(key);
                        if (at != c.lists.end())
                            for (std::size_t i = 0; i + 1 < at->second.size(); i += 2)
                                rows.append(py::make_tuple(at->second[i], at->second[i + 1]));
                        return rows;
                    },
                    [key](Contact& c, const py::object& rows) {
                        std::vector<double> list;
                        for (const py::handle row : rows) {
                            const std::vector<double> pair = row.cast<std::vector<double>>();
                            if (pair.size() != 2) bad(key + ": expected pairs (a, b), got a row of " + std::to_string(pair.size()));
                            list.insert(list.end(), pair.begin(), pair.end());
                        }
                        if (list.empty()) c.lists.erase(key); else c.lists[key] = list;
                    },
                    docs[key].c_str());
                continue;
            }
            if (p.kind == LawParameter::Kind::rows || p.kind == LawParameter::Kind::direction_rows) {
                contact.def_property(  // a table: rows of equal length (a list of lists); empty: not given
                    key.c_str(),
                    [key](const Contact& c) {
                        py::list rows;
                        if (const auto at = c.tables.find(key); at != c.tables.end())
                            for (Eigen::Index i = 0; i < at->second.rows(); ++i) {
                                std::vector<double> row(static_cast<std::size_t>(at->second.cols()));
                                for (Eigen::Index j = 0; j < at->second.cols(); ++j) row[static_cast<std::size_t>(j)] = at->second(i, j);
                                rows.append(py::cast(row));
                            }
                        return rows;
                    },
                    [key](Contact& c, const py::object& value) {
                        std::vector<std::vector<double>> rows;
                        if (!value.is_none())
                            for (const py::handle row : value) rows.push_back(row.cast<std::vector<double>>());
                        if (rows.empty()) {
                            c.tables.erase(key);
                            return;
                        }
                        Eigen::MatrixXd table(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(rows[0].size()));
                        for (std::size_t i = 0; i < rows.size(); ++i) {
                            if (rows[i].size() != rows[0].size())
                                bad(key + ": row " + std::to_string(i + 1) + " has " + std::to_string(rows[i].size()) +
                                    " entries: allowed " + std::to_string(rows[0].size()) + " as row 1");
                            for (std::size_t j = 0; j < rows[i].size(); ++j)
                                table(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j];
                        }
                        c.tables[key] = table;
                    },
                    docs[key].c_str());
                continue;
            }
            if (p.kind == LawParameter::Kind::direction) {  // a vector over the DOFs; empty: not given
                contact.def_property(
                    key.c_str(),
                    [key](const Contact& c) {
                        const auto at = c.lists.find(key);
                        return at == c.lists.end() ? std::vector<double>() : at->second;
                    },
                    [key](Contact& c, const py::object& v) {
                        const Eigen::VectorXd d = v.is_none() ? Eigen::VectorXd() : to_vector(v, key.c_str());
                        if (d.size() == 0) c.lists.erase(key); else c.lists[key].assign(d.data(), d.data() + d.size());
                    },
                    docs[key].c_str());
                continue;
            }
            contact.def_property(
                key.c_str(), [p](const Contact& c) { return p.get(c); }, [p](Contact& c, double v) { p.set(c, v); },
                docs[key].c_str());
        }
    }

    py::class_<AbsorberParameters> absorber_parameters(m, "AbsorberParameters", "The paper's absorber, nondimensional (model.hpp)");
    absorber_parameters
        .def(py::init<>())
        .def_readwrite("mass_ratio", &AbsorberParameters::mass_ratio, "r = m2 / m1")
        .def_readwrite("tuning_ratio", &AbsorberParameters::tuning_ratio, "wa = omega2 / omega1")
        .def_readwrite("friction_coefficient", &AbsorberParameters::friction_coefficient, "mu")
        .def_readwrite("excitation", &AbsorberParameters::excitation, "fe = F0 / N")
        .def("validate", [](const AbsorberParameters& p, const std::string& law) { p.validate(parse_friction_law(law)); },
             py::arg("law"));
    m.def(
        "check_given_preset_parameters",
        [](const std::string& law, const AbsorberParameters& p, const std::vector<std::string>& keywords) {
            check_given_preset_parameters(parse_friction_law(law), p, keywords);
        },
        "model.hpp: the checks hbf applies to the law's parameters given (does it read them; an explicit 0)",
        py::arg("law"), py::arg("parameters"), py::arg("keywords"));
    // The laws' own preset parameters (model.hpp: preset_parameters), by their C++ names.
    for (const PresetParameter& p : preset_parameters()) {
        double AbsorberParameters::*field = p.field;
        absorber_parameters.def_property(
            p.field_name, [field](const AbsorberParameters& a) { return a.*field; },
            [field](AbsorberParameters& a, double v) { a.*field = v; },
            (std::string(p.symbol) + ": " + p.help + " (" + laws_reading(p.symbol) + ")").c_str());
    }

    py::class_<PySystem>(m, "System", "A linear structure with friction contacts (model.hpp)")
        .def(py::init([](const py::object& mass, const py::object& stiffness, const py::object& excitation,
                         const py::object& damping, const py::object& contacts, const py::object& excitation_harmonic,
                         const py::object& static_load) {
                 PySystem s;
                 s.system.mass = to_sparse(mass, "mass");
                 s.system.stiffness = to_sparse(stiffness, "stiffness");
                 s.system.damping = damping.is_none() ? SparseMatrix(s.system.mass.rows(), s.system.mass.cols())
                                                      : to_sparse(damping, "damping");
                 s.system.excitation = to_vector(excitation, "excitation");
                 s.system.excitation_harmonic = to_int(excitation_harmonic, "excitation_harmonic");
                 s.system.contacts = to_contacts(contacts, "contacts");
                 if (!static_load.is_none()) s.system.static_load = to_vector(static_load, "static_load");
                 s.system.validate();
                 return s;
             }),
             py::arg("mass"), py::arg("stiffness"), py::arg("excitation"), py::arg("damping") = py::none(),
             py::arg("contacts") = py::none(), py::arg("excitation_harmonic") = 1, py::arg("static_load") = py::none())
        .def_property(
            "mass", [](const PySystem& s) { return from_sparse(s.system.mass); },
            [](PySystem& s, const py::object& v) { s.system.mass = to_sparse(v, "mass"); })
        .def_property(
            "stiffness", [](const PySystem& s) { return from_sparse(s.system.stiffness); },
            [](PySystem& s, const py::object& v) { s.system.stiffness = to_sparse(v, "stiffness"); })
        .def_property(
            "damping", [](const PySystem& s) { return from_sparse(s.system.damping); },
            [](PySystem& s, const py::object& v) { s.system.damping = to_sparse(v, "damping"); })
        .def_property(
            "excitation", [](const PySystem& s) { return to_list(s.system.excitation); },
            [](PySystem& s, const py::object& v) { s.system.excitation = to_vector(v, "excitation"); })
        .def_property(
            "excitation_harmonic", [](const PySystem& s) { return s.system.excitation_harmonic; },
            [](PySystem& s, const py::object& h) { s.system.excitation_harmonic = to_int(h, "excitation_harmonic"); })
        .def_property(
            "static_load", [](const PySystem& s) { return to_list(s.system.static_load); },
            [](PySystem& s, const py::object& v) {
                s.system.static_load = v.is_none() ? Eigen::VectorXd() : to_vector(v, "static_load");
            },
            "F_s, the constant load (N entries, or [] / None for none): harmonic balance carries it on harmonic 0")
        .def_property(
            "contacts", [](const PySystem& s) { return s.system.contacts; },
            [](PySystem& s, const py::object& c) {
                s.system.contacts = to_contacts(c, "contacts");
                s.interfaces.clear();  // the nodes' contacts are gone
            })
        .def_property_readonly(
            "cyclic",
            [](const PySystem& s) -> py::object {
                if (!s.system.cyclic.active()) return py::none();
                py::dict d;
                d["sectors"] = s.system.cyclic.sectors;
                d["engine_order"] = s.system.cyclic.engine_order;
                py::list pairs;
                for (const auto& [dependent, master] : s.system.cyclic.neighbours)
                    pairs.append(py::make_tuple(dependent, master));
                d["neighbours"] = pairs;
                return std::move(d);
            },
            "a sector model's cyclic symmetry (a system file's [cyclic]): dict sectors, engine_order and "
            "neighbours, the pairs (DOF, the next sector's DOF it is), 0-based; None for a whole structure")
        .def_property_readonly(
            "interfaces",
            [](const PySystem& s) {
                py::list out;
                for (const InterfaceContacts& f : s.interfaces) out.append(interface_dict(f));
                return out;
            },
            "the meshed interfaces (add_interface, a file's [[interface]]): dicts name, first, count, dimension; "
            "interface k's nodes are contacts[first:first + count], in node order")
        .def(
            "_add_interface",
            [](PySystem& s, const py::object& nodes, const py::object& normal, const Contact& contact,
               const py::object& tangent, const py::object& area, double preload_pressure, const std::string& name) {
                if (s.reduction)
                    bad("add_interface: the system is already reduced: add the interface to the FE system, then "
                        "reduce it (hbfriction.reduce keeps the nodes' DOFs)");
                ContactInterface i;
                i.name = name.empty() ? "interface " + std::to_string(s.interfaces.size() + 1) : name;
                i.nodes = to_nodes(nodes, "nodes");
                i.normals = to_rows(normal, "normal");
                if (!tangent.is_none()) i.tangents = to_rows(tangent, "tangent");
                if (!area.is_none()) i.areas = to_vector(area, "area");
                i.prototype = contact;
                i.preload_pressure = preload_pressure;
                const int n = s.system.dofs();
                // A DOF in two interfaces would carry two contacts (pressed and rubbed twice):
                // the earlier interfaces' DOFs are those their contacts' directions move.
                for (const InterfaceContacts& earlier : s.interfaces)
                    for (int c = earlier.first; c < earlier.first + earlier.count; ++c) {
                        const Eigen::MatrixXd w = s.system.contact_directions(s.system.contacts[static_cast<std::size_t>(c)]);
                        for (std::size_t k = 0; k < i.nodes.size(); ++k)
                            for (int d : i.nodes[k])
                                if (d >= 0 && d < n && w.row(d).cwiseAbs().maxCoeff() > 0.0)
                                    bad("nodes: node " + std::to_string(k) + "'s DOF " + std::to_string(d) +
                                        " is also a node DOF of interface '" + earlier.name +
                                        "': allowed each DOF in one interface (two would press and rub it twice)");
                    }
                std::vector<Contact> added;
                try {
                    added = interface_contacts(i, n, n, [](int d) { return d; });
                } catch (const InvalidInput& e) {  // the library counts nodes, rows and DOFs from 1, as the files do
                    bad(std::string(e.what()) + " (nodes, rows and DOFs counted from 1 here, as in a system file: "
                                                "the Python index is one less)");
                }
                System next = s.system;
                const InterfaceContacts where{i.name, static_cast<int>(next.contacts.size()),
                                              static_cast<int>(added.size()), i.dimension()};
                next.contacts.insert(next.contacts.end(), added.begin(), added.end());
                if (preload_pressure > 0.0) {
                    if (next.static_load.size() != n) next.static_load = Eigen::VectorXd::Zero(n);
                    next.static_load += interface_load(i, n);
                }
                next.validate();
                s.system = std::move(next);
                s.interfaces.push_back(where);
                return interface_dict(where);
            })
        .def_property_readonly(
            "recovery",
            [](const PySystem& s) -> py::object {
                if (!s.reduction) return py::none();
                const Eigen::MatrixXd& t = s.reduction->recovery;
                py::array_t<double> out({t.rows(), t.cols()});
                auto v = out.mutable_unchecked<2>();
                for (Eigen::Index i = 0; i < t.rows(); ++i)
                    for (Eigen::Index j = 0; j < t.cols(); ++j) v(i, j) = t(i, j);
                return std::move(out);
            },
            "a reduced system's recovery matrix T (FE DOFs x reduced coordinates, y = T q; None unreduced)")
        .def_property_readonly(
            "retained", [](const PySystem& s) -> py::object {
                if (!s.reduction) return py::none();
                return py::cast(s.reduction->retained);
            },
            "a reduced system's FE DOF (0-based) of each retained coordinate (the first ones; None unreduced)")
        .def_property_readonly(
            "mode_frequencies", [](const PySystem& s) -> py::object {
                if (!s.reduction) return py::none();
                return py::cast(to_list(s.reduction->mode_frequencies));
            },
            "a reduced system's kept normal modes' frequencies sqrt(lambda_j) (fixed-interface; macneal: free)")
        .def_property_readonly(
            "dropped_mass_fraction", [](const PySystem& s) -> py::object {
                if (!s.reduction || s.reduction->dropped_mass.size() == 0) return py::none();
                return py::cast(s.reduction->dropped_mass_fraction);
            },
            "massless-boundary: the mass its massless retained coordinates drop, as a fraction of the FE "
            "model's trace(M) (None otherwise)")
        .def_property_readonly(
            "reduction_warnings",
            [](const PySystem& s) { return s.reduction ? s.reduction->warnings() : std::vector<std::string>(); },
            "what makes a reduced model doubtful (a massless boundary dropping more than 1 % of the mass)")
        .def(
            "fe_outputs",
            [](const PySystem& s, const std::vector<int>& dofs) {
                if (!s.reduction) bad("fe_outputs: the system is not reduced (its outputs are its DOFs)");
                std::vector<Output> fe;
                for (int d : dofs) {
                    if (d < 0 || d >= s.reduction->dofs())
                        bad("fe_outputs: FE DOF " + std::to_string(d) + " is out of range: allowed 0.." +
                            std::to_string(s.reduction->dofs() - 1));
                    fe.push_back(Output::dof(d));
                }
                return reduced_outputs(fe, *s.reduction);
            },
            py::arg("dofs"), "outputs of FE DOFs (0-based; named y<dof + 1>) as rows of the recovery matrix")
        .def_property(
            "outputs", [](const PySystem& s) { return s.outputs; },
            [](PySystem& s, const std::vector<Output>& o) {
                for (const Output& out : o) out.validate(s.system.dofs());
                s.outputs = o;
            })
        .def_property_readonly("dofs", [](const PySystem& s) { return s.system.dofs(); })
        .def_property_readonly("law", &PySystem::law_name)
        .def_property_readonly("source", [](const PySystem& s) { return s.source; })
        .def_property_readonly("absorber", [](const PySystem& s) { return s.absorber; })
        .def_property_readonly("file_settings",
                               [](const PySystem& s) {
                                   py::dict d;
                                   if (s.choices.omega_start) d["omega_start"] = *s.choices.omega_start;
                                   if (s.choices.omega_end) d["omega_end"] = *s.choices.omega_end;
                                   if (s.choices.harmonics) d["harmonics"] = *s.choices.harmonics;
                                   if (s.choices.time_samples) d["time_samples"] = *s.choices.time_samples;
                                   if (s.choices.modes) d["modes"] = *s.choices.modes;
                                   if (s.choices.odd_harmonics) d["odd_harmonics"] = *s.choices.odd_harmonics;
                                   if (s.choices.jacobian) d["jacobian"] = to_string(*s.choices.jacobian);
                                   return d;
                               })
        .def("validate", [](const PySystem& s) {
            s.system.validate();
            for (const Output& o : s.outputs) o.validate(s.system.dofs());
        })
        .def("warnings", [](const PySystem& s) { return s.system.warnings(); })
        .def("copy", [](const PySystem& s) { return s; })
        .def("__repr__", [](const PySystem& s) {
            return "hbfriction.System(" + std::to_string(s.system.dofs()) + " DOFs, " +
                   std::to_string(s.system.contacts.size()) + " contact(s): " + s.law_name() +
                   (s.source.empty() ? std::string() : ", from " + s.source) + ")";
        });

    m.def(
        "friction_absorber",
        [](const AbsorberParameters& p, const std::string& law) {
            PySystem s;
            s.system = friction_absorber(p, parse_friction_law(law));
            s.absorber = p;
            s.outputs = {Output::dof(0), Output::dof(1)};
            s.source = "absorber";
            return s;
        },
        py::arg("parameters"), py::arg("law"));
    m.def(
        "read_system_config",
        [](const std::string& path) {
            PySystem s;
            static_cast<io::SystemConfig&>(s) = io::read_system_config(path);
            s.source = path;
            return s;
        },
        py::arg("path"));
    m.def(
        "reduce_system",
        [](const PySystem& s, int modes, const std::string& method, const py::object& interface,
           const py::object& ratios, const py::object& rayleigh) {
            if (s.reduction) bad("reduce: the system is already reduced");
            ReductionOptions o;
            o.modes = modes;
            o.method = parse_reduction_method(method);
            const int n = s.system.dofs();
            if (interface.is_none()) {  // the DOFs the contacts act on, ascending
                for (Eigen::Index i = 0; i < n; ++i)
                    for (const Contact& c : s.system.contacts)
                        if (s.system.contact_directions(c).row(i).cwiseAbs().maxCoeff() > 0.0) {
                            o.interface_dofs.push_back(static_cast<int>(i));
                            break;
                        }
            } else {
                for (const std::vector<int>& row : to_nodes(interface, "interface"))
                    o.interface_dofs.insert(o.interface_dofs.end(), row.begin(), row.end());
            }
            if (!ratios.is_none() && !rayleigh.is_none())
                bad("reduce: damping_ratios and rayleigh are alternatives: give one");
            if (!ratios.is_none()) {
                const Eigen::VectorXd z = to_vector(ratios, "damping_ratios");
                o.damping = ReductionOptions::Damping::modal;
                o.modal_ratios.assign(z.data(), z.data() + z.size());
                if (o.modal_ratios.empty()) bad("reduction.damping_ratios: empty: allowed ratios in [0, 1)");
            } else if (!rayleigh.is_none()) {
                const Eigen::VectorXd ab = to_vector(rayleigh, "rayleigh");
                if (ab.size() != 2) bad("reduction.rayleigh: " + std::to_string(ab.size()) + " numbers: allowed (a, b)");
                o.damping = ReductionOptions::Damping::rayleigh;
                o.rayleigh_mass = ab(0);
                o.rayleigh_stiffness = ab(1);
            }
            ReducedSystem r = reduce(s.system, o);
            PySystem out;
            static_cast<io::SystemConfig&>(out) = s;
            out.absorber = s.absorber;
            out.source = s.source;
            out.system = std::move(r.system);
            out.system.validate();
            out.outputs = s.outputs.empty() ? std::vector<Output>() : reduced_outputs(s.outputs, r.model);
            out.reduction = std::make_shared<const ReducedModel>(std::move(r.model));
            return out;
        },
        py::arg("system"), py::arg("modes"), py::arg("method"), py::arg("interface"), py::arg("damping_ratios"),
        py::arg("rayleigh"));
    m.def("exact_solver_refusal", [](const PySystem& s) { return exact_solver_supports(s.system) ? std::string() : exact_solver_refusal(s.system); });
    m.def("exact_cost_refusal", [](const PySystem& s, double omega) { return exact_cost_refusal(s.system, omega); });
    m.def(
        "exact_polish_refusal",
        [](const PySystem& s, double omega, int modes) { return exact_polish_refusal(s.system, omega, modes); },
        py::arg("system"), py::arg("omega") = 0.0, py::arg("modes") = 0);
    m.def("stability_refusal", [](const PySystem& s) { return stability_refusal(s.system); });
}

}  // namespace hbf::python
