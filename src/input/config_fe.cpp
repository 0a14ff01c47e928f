// hbfriction — system files (config.hpp): the finite-element tables, [reduction] (reduction.hpp)
// and [[interface]] (interface.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>

#include "input/config_reader.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/interface.hpp"
#include "hbf/reduction.hpp"

namespace hbf::io::detail {

/// [reduction]: the FE system of [structure] and [[contact]] reduced onto its interface
/// (reduction.hpp); the contacts, loads and outputs, given on FE DOFs, are carried over.
void read_reduction(const Reader& r, const toml::node& node, SystemConfig& config,
                    const std::vector<toml::source_region>& contact_lines,
                    const std::vector<ContactInterface>& interfaces,
                    const std::vector<toml::source_region>& interface_lines, const ClampedSystem* clamped) {
    const std::string& path = r.file;
    const toml::table* t = node.as_table();
    if (!t) fail(path, node.source(), "reduction", "expected a table [reduction]");
    r.only(*t, config_keys_of("reduction"), "reduction");
    const System& fe = config.system;
    // n: the file's DOFs; a clamped model's DOF d is its index (the same without clamping).
    const int n = clamped ? static_cast<int>(clamped->index.size()) : fe.dofs();
    const auto index = [clamped](int d) { return clamped ? clamped->index[static_cast<std::size_t>(d)] : d; };
    ReductionOptions o;
    if (const toml::node* v = t->get("method")) {
        const auto name = v->as_string();
        if (!name) fail(path, v->source(), "reduction.method", "expected a string: craig-bampton, massless-boundary or macneal");
        try {
            o.method = parse_reduction_method(name->get());
        } catch (const InvalidInput& e) {
            fail(path, v->source(), "reduction.method", e.what());
        }
    }
    const toml::node* modes = t->get("modes");
    if (!modes) fail(path, t->source(), "reduction.modes", "missing: the number of normal modes kept (0 = static condensation for craig-bampton and massless-boundary)");
    o.modes = r.integer(*modes, "reduction.modes");
    if (const toml::node* v = t->get("interface")) {
        // 1-based FE DOFs: a list, or a Matrix Market index vector (one column).
        for (int d : r.dof_list(*v, "reduction.interface", n)) {
            if (index(d) < 0)
                fail(path, v->source(), "reduction.interface",
                     "DOF " + std::to_string(d + 1) + " is clamped (structure.fixed): allowed free DOFs");
            o.interface_dofs.push_back(index(d));
        }
    } else {
        // Default: the DOFs the contacts act on, ascending, then the interfaces' nodes in order.
        std::set<int> dofs;
        for (const Contact& c : fe.contacts) {
            const Eigen::MatrixXd w = fe.contact_directions(c);
            for (Eigen::Index i = 0; i < w.rows(); ++i)
                if (w.row(i).cwiseAbs().maxCoeff() > 0.0) dofs.insert(static_cast<int>(i));
        }
        o.interface_dofs.assign(dofs.begin(), dofs.end());
        for (const ContactInterface& iface : interfaces)
            for (const std::vector<int>& node : iface.nodes)
                for (int d : node)
                    if (index(d) >= 0 && dofs.insert(index(d)).second) o.interface_dofs.push_back(index(d));
    }
    if (const toml::node* v = t->get("retain_loads")) {
        const auto flag = v->as_boolean();
        if (!flag) fail(path, v->source(), "reduction.retain_loads", "expected true or false");
        o.retain_loads = flag->get();
    }
    const toml::node* ratios = t->get("damping_ratios");
    const toml::node* rayleigh = t->get("rayleigh");
    if (ratios && rayleigh) fail(path, rayleigh->source(), "reduction.rayleigh", "given with reduction.damping_ratios: allowed one of them");
    if (ratios) {
        o.damping = ReductionOptions::Damping::modal;
        o.modal_ratios = r.list(*ratios, "reduction.damping_ratios");
    }
    if (rayleigh) {
        const std::vector<double> ab = r.list(*rayleigh, "reduction.rayleigh");
        if (ab.size() != 2) fail(path, rayleigh->source(), "reduction.rayleigh", "expected [a, b]: C_r = a M_r + b K_r");
        o.damping = ReductionOptions::Damping::rayleigh;
        o.rayleigh_mass = ab[0];
        o.rayleigh_stiffness = ab[1];
    }
    ReducedSystem reduced;
    try {
        reduced = reduce(fe, o);
        if (clamped) reduced.model = unclamped(std::move(reduced.model), *clamped);
        config.outputs = reduced_outputs(config.outputs, reduced.model);
    } catch (const InvalidInput& e) {
        const std::string what = e.what();
        if (what.rfind("contact ", 0) == 0) {
            const std::size_t c = std::stoul(what.substr(8)) - 1;
            fail(path, c < contact_lines.size() ? contact_lines[c] : t->source(), "contact[" + std::to_string(c + 1) + "]", what);
        }
        std::string key = "reduction";
        toml::source_region where = t->source();
        for (const char* k : {"interface", "modes", "method", "damping_ratios", "rayleigh"})
            if (what.rfind("reduction." + std::string(k), 0) == 0) {
                key = "reduction." + std::string(k);
                if (const toml::node* v = t->get(k)) where = v->source();
            }
        if (what.rfind("reduction.damping:", 0) == 0) key = "reduction";
        fail(path, where, key, what);
    }
    std::vector<std::string> contact_keys;
    std::vector<toml::source_region> lines = contact_lines;
    for (std::size_t c = 0; c < reduced.system.contacts.size(); ++c) contact_keys.push_back("contact[" + std::to_string(c + 1) + "]");
    const ReducedModel& model = reduced.model;
    config.interfaces = add_interface_contacts(path, interfaces, interface_lines, reduced.system, n, model.reduced(),
                           [&model](int dof) { return model.coordinate(dof); }, contact_keys, lines);
    try {
        reduced.system.validate();
    } catch (const InvalidInput& e) {
        const std::string what = e.what();
        if (what.rfind("contact ", 0) == 0) {
            const std::size_t c = std::stoul(what.substr(8)) - 1;
            if (c < contact_keys.size()) fail(path, lines[c], contact_keys[c], what);
        }
        fail(path, t->source(), "reduction", what);
    }
    config.system = std::move(reduced.system);
    config.reduction = std::make_shared<const ReducedModel>(std::move(reduced.model));
}

ContactInterface read_interface(const Reader& r, const toml::table& t, int index, int dofs) {
    const std::string where = "interface[" + std::to_string(index + 1) + "]";
    ContactInterface iface;
    const toml::node* law_node = t.get("law");
    if (!law_node || !law_node->is_string())
        fail(r.file, law_node ? law_node->source() : t.source(), where + ".law", "missing: a string (elastic or unilateral)");
    try {
        iface.prototype.law = parse_friction_law(law_node->as_string()->get());
    } catch (const InvalidInput& e) {
        fail(r.file, law_node->source(), where + ".law", e.what());
    }
    // Keys: the interface's own, and the law's numbers (directions come from the frames; the
    // preload is given as a pressure).
    std::set<std::string> allowed = config_keys_of("interface");
    const std::vector<LawParameter> parameters = contact_law(iface.prototype.law).parameters();
    if (std::none_of(parameters.begin(), parameters.end(),
                     [](const LawParameter& p) { return std::string(p.key) == "normal_direction"; }))
        fail(r.file, law_node->source(), where + ".law",
             "'" + law_node->as_string()->get() + "' has no normal direction: allowed elastic or unilateral (an "
             "interface's nodes press on and lift off the other side; a law along one direction is a [[contact]] table)");
    for (const LawParameter& p : parameters)
        if (p.scalar() && std::string(p.key) != "preload") allowed.insert(p.key);
    r.only(t, allowed, where);
    if (const toml::node* v = t.get("name")) {
        if (!v->is_string()) fail(r.file, v->source(), where + ".name", "expected a string");
        iface.name = v->as_string()->get();
    }
    auto rows = [&](const toml::node& v, const std::string& key) { return r.rows(v, key); };
    const toml::node* nodes = t.get("nodes");
    if (!nodes) fail(r.file, t.source(), where + ".nodes", "missing: each node's FE DOFs (1-based), [[x, y, z], ...] or an n x 3 (2D: n x 2) .mtx");
    const Eigen::MatrixXd node_dofs = rows(*nodes, where + ".nodes");
    for (Eigen::Index k = 0; k < node_dofs.rows(); ++k) {
        std::vector<int> node;
        for (Eigen::Index j = 0; j < node_dofs.cols(); ++j) {
            const double d = node_dofs(k, j);
            if (!(d == std::floor(d)) || std::abs(d) > 1e9)
                fail(r.file, nodes->source(), where + ".nodes",
                     "node " + std::to_string(k + 1) + ": " + format_number(d) + " is not a DOF: allowed integers 1.." + std::to_string(dofs));
            node.push_back(static_cast<int>(d) - 1);
        }
        iface.nodes.push_back(std::move(node));
    }
    const toml::node* normal = t.get("normal");
    if (!normal) fail(r.file, t.source(), where + ".normal", "missing: the closing direction n (one for all nodes, or one per node)");
    iface.normals = rows(*normal, where + ".normal");
    if (const toml::node* v = t.get("tangent")) iface.tangents = rows(*v, where + ".tangent");
    if (const toml::node* v = t.get("area")) {
        if (v->is_number()) {
            iface.areas = Eigen::VectorXd::Constant(1, r.number(*v, where + ".area"));
        } else {
            iface.areas = r.vector(*v, where + ".area", -1);
        }
    }
    for (const LawParameter& p : parameters)
        if (p.scalar())
            if (const toml::node* v = t.get(p.key)) p.set(iface.prototype, r.number(*v, where + "." + p.key));
    if (const toml::node* v = t.get("preload_pressure")) iface.preload_pressure = r.number(*v, where + ".preload_pressure");
    try {
        iface.validate(dofs);
    } catch (const InvalidInput& e) {
        const std::string what = e.what();
        std::string key = where;
        for (const char* k : {"nodes", "normal", "tangent", "area", "preload_pressure", "law"})
            if (what.find(std::string(": ") + k + ":") != std::string::npos) {
                key = where + "." + k;
                break;
            }
        fail(r.file, t.source(), key, what);
    }
    return iface;
}

std::vector<InterfaceContacts> add_interface_contacts(const std::string& path, const std::vector<ContactInterface>& interfaces,
                            const std::vector<toml::source_region>& interface_lines, System& system, int dofs,
                            int coordinates, const std::function<int(int)>& coordinate,
                            std::vector<std::string>& contact_keys, std::vector<toml::source_region>& contact_lines) {
    std::vector<InterfaceContacts> out;
    // A DOF in two interfaces would carry two contacts (the forces added twice): refused.
    std::map<int, std::size_t> owner;  // FE DOF -> the interface that has it
    for (std::size_t i = 0; i < interfaces.size(); ++i)
        for (std::size_t k = 0; k < interfaces[i].nodes.size(); ++k)
            for (int d : interfaces[i].nodes[k]) {
                const auto [at, added] = owner.emplace(d, i);
                if (!added && at->second != i)
                    fail(path, interface_lines[i], "interface[" + std::to_string(i + 1) + "].nodes",
                         "node " + std::to_string(k + 1) + "'s DOF " + std::to_string(d + 1) + " is also a node DOF of interface[" +
                             std::to_string(at->second + 1) + "]: allowed each DOF in one interface (two would press "
                             "and rub it twice)");
            }
    for (std::size_t i = 0; i < interfaces.size(); ++i) {
        const std::string where = "interface[" + std::to_string(i + 1) + "]";
        out.push_back({interfaces[i].name.empty() ? "interface " + std::to_string(i + 1) : interfaces[i].name,
                       static_cast<int>(system.contacts.size()), 0, interfaces[i].dimension()});
        std::vector<Contact> contacts;
        try {
            contacts = interface_contacts(interfaces[i], dofs, coordinates, coordinate);
        } catch (const InvalidInput& e) {
            fail(path, interface_lines[i], where + ".nodes", e.what());
        }
        for (std::size_t k = 0; k < contacts.size(); ++k) {
            contacts[k].label = where + " node " + std::to_string(k + 1);
            system.contacts.push_back(std::move(contacts[k]));
            contact_keys.push_back(where + " node " + std::to_string(k + 1));
            contact_lines.push_back(interface_lines[i]);
        }
        out.back().count = static_cast<int>(contacts.size());
    }
    return out;
}

}  // namespace hbf::io::detail
