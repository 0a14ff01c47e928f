// hbfriction — the TOML system file (config.hpp): structure, contacts, outputs and the
// [frequency] and [solver] settings read and checked, naming the key and line of a bad value.
#include "hbf/config.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/harmonic_balance.hpp"
#include "input/config_reader.hpp"
#include "hbf/interface.hpp"

namespace hbf::io {

using detail::fail;
using detail::Reader;

namespace {

/// Limits checked before the TOML parser sees a file: it recurses once per level of a dotted
/// table header and crashed (stack overflow) on a 40,000-level one. A system file needs 3.
constexpr std::uintmax_t max_config_bytes = 64u << 20;
constexpr int max_config_nesting = 32;

/// Throws naming the line where dotted key parts or nested brackets exceed max_config_nesting.
/// A light scan: strings and comments are skipped, keys are read up to '=' (at the top level,
/// in a [header], and after '{' or ',' inside an inline table).
void check_nesting(const std::string& path, const std::string& text) {
    int line = 1, dots = 0;
    bool key = true;
    std::vector<char> open;  // '[' and '{' of values
    auto deep = [&](const char* what) {
        throw InvalidInput(path + ":" + std::to_string(line) + ": " + what + " nested deeper than " +
                           std::to_string(max_config_nesting) + " levels: allowed at most " +
                           std::to_string(max_config_nesting) + " (a system file needs 3)");
    };
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') {
            ++line;
            if (open.empty()) {
                key = true;
                dots = 0;
            }
        } else if (c == '#') {
            while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
        } else if (c == '"' || c == '\'') {
            const bool triple = text.compare(i, 3, std::string(3, c)) == 0;
            i += triple ? 3 : 1;
            while (i < text.size()) {
                if (c == '"' && text[i] == '\\') {
                    if (i + 1 < text.size() && text[i + 1] == '\n') ++line;
                    i += 2;
                    continue;
                }
                if (text[i] == '\n') {
                    if (!triple) break;  // an unterminated string: the parser reports it
                    ++line;
                }
                if (text[i] == c && (!triple || text.compare(i, 3, std::string(3, c)) == 0)) {
                    if (triple) i += 2;
                    break;
                }
                ++i;
            }
            if (i < text.size() && text[i] == '\n') --i;  // counted by the main loop
        } else if (key) {
            if (c == '.' && ++dots > max_config_nesting) deep("dotted key parts");
            if (c == '=') {
                key = false;
                dots = 0;
            }
        } else if (c == '[' || c == '{') {
            open.push_back(c);
            if (static_cast<int>(open.size()) > max_config_nesting) deep("brackets");
            if (c == '{') key = true;
        } else if (c == ']' || c == '}') {
            if (!open.empty()) open.pop_back();
        } else if (c == ',' && !open.empty() && open.back() == '{') {
            key = true;
        }
    }
}


/// One [[contact]] table. `neighbour` (0-based, else -1): the next sector's DOF that
/// neighbour_dof names (a sector model's contact across the cut; the caller places it).
Contact read_contact(const Reader& r, const toml::table& t, int index, int dofs, bool sector, int& neighbour) {
    neighbour = -1;
    const std::string where = "contact[" + std::to_string(index + 1) + "]";
    Contact c;
    const toml::node* law_node = t.get("law");
    if (!law_node) fail(r.file, t.source(), where + ".law", "missing: a string (" + contact_law_names() + ")");
    if (!law_node->is_string())
        fail(r.file, law_node->source(), where + ".law", "expected a string: " + contact_law_names());
    try {
        c.law = parse_friction_law(law_node->as_string()->get());
    } catch (const InvalidInput& e) {
        fail(r.file, law_node->source(), where + ".law", e.what());
    }
    std::set<std::string> allowed = config_keys_of("contact");
    // the law's parameters (contact_law.hpp)
    const std::vector<LawParameter> parameters = contact_law(c.law).parameters();
    for (const LawParameter& p : parameters) allowed.insert(p.key);
    if (!contact_law(c.law).has_friction_limit()) allowed.erase("friction_limit");  // mu N instead
    for (auto&& [key, node] : t) {
        const std::string k(key.str());
        if (allowed.count(k) == 0) {
            std::string list;
            for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
            fail(r.file, key.source(), where + "." + k, "does not apply to law '" + to_string(c.law) + "': allowed " + list);
        }
    }
    auto dof = [&](const char* key) {
        const toml::node* node = t.get(key);
        const int value = r.integer(*node, where + "." + key);
        if (value < 1 || value > dofs)
            fail(r.file, node->source(), where + "." + key,
                 std::to_string(value) + " is out of range: allowed 1.." + std::to_string(dofs) + " (1-based DOF)");
        return value - 1;
    };
    if (const toml::node* direction = t.get("force_direction")) {
        if (t.get("dof") || t.get("other_dof") || t.get("neighbour_dof"))
            fail(r.file, direction->source(), where + ".force_direction",
                 "given together with dof / other_dof: a contact is either a DOF pair (or a DOF and the ground) or a "
                 "force direction");
        c.direction = r.vector(*direction, where + ".force_direction", dofs);
    } else {
        if (!t.get("dof")) fail(r.file, t.source(), where + ".dof", "missing: the contact's DOF (1-based), or force_direction");
        c.dof = dof("dof");
        if (const toml::node* node = t.get("neighbour_dof")) {
            if (!sector)
                fail(r.file, node->source(), where + ".neighbour_dof",
                     "a DOF of the next sector needs a sector model: allowed with a [cyclic] table only");
            if (t.get("other_dof"))
                fail(r.file, node->source(), where + ".neighbour_dof",
                     "given together with other_dof: a contact joins dof to other_dof or to the next sector's neighbour_dof");
            neighbour = dof("neighbour_dof");
        }
        if (t.get("other_dof")) {
            c.other_dof = dof("other_dof");
            if (c.other_dof == c.dof)
                fail(r.file, t.get("other_dof")->source(), where + ".other_dof", "equals dof: a contact joins two different DOFs (omit other_dof for the ground)");
        }
    }
    if (contact_law(c.law).has_friction_limit()) {
        if (!t.get("friction_limit"))
            fail(r.file, t.source(), where + ".friction_limit", "missing: the slip force F_c = mu N (> 0)");
        c.friction_limit = r.number(*t.get("friction_limit"), where + ".friction_limit");
    }
    for (const LawParameter& p : parameters) {
        const toml::node* node = t.get(p.key);
        if (!node) continue;
        if (p.kind == LawParameter::Kind::direction) {  // a vector over the model's coordinates
            const Eigen::VectorXd v = r.vector(*node, where + "." + p.key, dofs);
            // The normal gap normal_direction^T y is a length (the gap, the penalty k_n, the
            // preload read in it): a unit vector, as an interface's normals.
            if (std::string(p.key) == "normal_direction" && v.allFinite() && v.norm() > 0.0 &&
                std::abs(v.norm() - 1.0) > 1e-6)  // (all zero: refused by the law's validation)
                fail(r.file, node->source(), where + "." + p.key,
                     "has length " + format_number(v.norm()) + ": allowed a unit vector (to 1e-6)");
            c.lists[p.key].assign(v.data(), v.data() + v.size());
            continue;
        }
        if (p.kind == LawParameter::Kind::rows || p.kind == LawParameter::Kind::direction_rows) {
            Eigen::MatrixXd table = r.rows(*node, where + "." + p.key);
            if (table.size() == 0)
                fail(r.file, node->source(), where + "." + p.key, std::string("expected a non-empty table (") + p.meaning + ")");
            if (p.kind == LawParameter::Kind::direction_rows && table.cols() != dofs)
                fail(r.file, node->source(), where + "." + p.key,
                     "rows of " + std::to_string(table.cols()) + " entries: allowed " + std::to_string(dofs) +
                         " (one per DOF: each row a direction)");
            c.tables[p.key] = std::move(table);
            continue;
        }
        if (p.kind != LawParameter::Kind::pairs) {
            p.set(c, r.number(*node, where + "." + p.key));
            continue;
        }
        // a table of pairs: [[a1, b1], [a2, b2], ...], kept row by row
        const toml::array* rows = node->as_array();
        if (!rows || rows->empty())
            fail(r.file, node->source(), where + "." + p.key, std::string("expected a non-empty array of pairs [a, b] (") + p.meaning + ")");
        std::vector<double>& list = c.lists[p.key];
        for (std::size_t i = 0; i < rows->size(); ++i) {
            const std::string at = where + "." + p.key + "[" + std::to_string(i + 1) + "]";
            const toml::array* pair = (*rows)[i].as_array();
            if (!pair || pair->size() != 2) fail(r.file, (*rows)[i].source(), at, "expected a pair of two numbers [a, b]");
            for (std::size_t j = 0; j < 2; ++j) list.push_back(r.number((*pair)[j], at));
        }
    }
    return c;
}

}  // namespace

namespace {

/// [cyclic]: sectors N >= 2, engine_order (an order outside 0..N-1 is taken as its alias EO mod
/// N, with a note), left and right (the cut faces: matched 1-based lists of equal length,
/// disjoint). right[i] is the next sector's DOF left[i].
void read_cyclic(const Reader& r, const toml::table& t, int dofs, SystemConfig& config) {
    r.only(t, config_keys_of("cyclic"), "cyclic");
    for (const char* key : {"sectors", "engine_order"})
        if (!t.get(key)) fail(r.file, t.source(), std::string("cyclic.") + key, "missing");
    CyclicSymmetry& c = config.system.cyclic;
    c.sectors = r.integer(*t.get("sectors"), "cyclic.sectors");
    if (c.sectors < 2)
        fail(r.file, t.get("sectors")->source(), "cyclic.sectors",
             std::to_string(c.sectors) + " is out of range: allowed >= 2 (the number of sectors of the wheel)");
    const int order = r.integer(*t.get("engine_order"), "cyclic.engine_order");
    c.engine_order = ((order % c.sectors) + c.sectors) % c.sectors;
    if (c.engine_order != order)
        config.cyclic_note = r.file + ": cyclic.engine_order = " + std::to_string(order) + " is engine order " +
                             std::to_string(c.engine_order) + " on " + std::to_string(c.sectors) +
                             " sectors (its alias: the same travelling wave)";
    auto faces = [&](const char* key) {
        std::vector<int> out;
        const toml::node* node = t.get(key);
        if (!node) return out;
        const toml::array* a = node->as_array();
        if (!a) fail(r.file, node->source(), std::string("cyclic.") + key, "expected a list of DOFs (1-based)");
        for (const toml::node& item : *a) {
            const int d = r.integer(item, std::string("cyclic.") + key);
            if (d < 1 || d > dofs)
                fail(r.file, item.source(), std::string("cyclic.") + key,
                     std::to_string(d) + " is out of range: allowed 1.." + std::to_string(dofs) + " (1-based DOF)");
            if (std::find(out.begin(), out.end(), d - 1) != out.end())
                fail(r.file, item.source(), std::string("cyclic.") + key, "DOF " + std::to_string(d) + " is listed twice");
            out.push_back(d - 1);
        }
        return out;
    };
    const std::vector<int> left = faces("left"), right = faces("right");
    if (left.size() != right.size())
        fail(r.file, (t.get("right") ? t.get("right") : t.get("left") ? t.get("left") : &t)->source(), "cyclic.right",
             std::to_string(right.size()) + " DOFs against " + std::to_string(left.size()) +
                 " in cyclic.left: allowed matched lists of equal length (right[i] is the next sector's left[i])");
    for (int d : right)
        if (std::find(left.begin(), left.end(), d) != left.end())
            fail(r.file, t.get("right")->source(), "cyclic.right",
                 "DOF " + std::to_string(d + 1) + " is in both cut faces: allowed disjoint left and right lists");
    for (std::size_t i = 0; i < left.size(); ++i) c.neighbours.emplace_back(right[i], left[i]);
}

/// The contacts across the cut (read_contact's neighbour): a neighbour DOF on the left cut face
/// is the matching right-face DOF of the model; any other is added as a DOF of its own (no
/// mass, stiffness or load: the next sector's copy, moved by the phase shift), after the
/// model's DOFs.
void place_neighbours(const std::vector<int>& neighbours, System& s) {
    const int n = s.dofs();
    std::vector<std::pair<int, int>> added;  // (new DOF, the next sector's DOF)
    for (std::size_t c = 0; c < neighbours.size(); ++c) {
        const int m = neighbours[c];
        if (m < 0) continue;
        int target = -1;
        for (const auto& [dependent, master] : s.cyclic.neighbours)
            if (master == m && dependent < n) target = dependent;
        for (const auto& [dependent, master] : added)
            if (master == m) target = dependent;
        if (target < 0) {
            target = n + static_cast<int>(added.size());
            added.emplace_back(target, m);
        }
        s.contacts[c].other_dof = target;
    }
    if (added.empty()) return;
    const auto grown = static_cast<Eigen::Index>(n + added.size());
    auto grow = [&](SparseMatrix& a) {
        SparseMatrix b(grown, grown);
        std::vector<Eigen::Triplet<double>> entries;
        for (int k = 0; k < a.outerSize(); ++k)
            for (SparseMatrix::InnerIterator it(a, k); it; ++it) entries.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
        b.setFromTriplets(entries.begin(), entries.end());
        a = b;
    };
    grow(s.mass);
    grow(s.stiffness);
    grow(s.damping);
    s.excitation.conservativeResize(grown);
    s.excitation.tail(grown - n).setZero();
    if (s.static_load.size() == n) {
        s.static_load.conservativeResize(grown);
        s.static_load.tail(grown - n).setZero();
    }
    for (const auto& pair : added) s.cyclic.neighbours.push_back(pair);
}

}  // namespace

/// One [[output]] table: `dof = i` (named y<i>), or `name` and `row` (N numbers, or a
/// Matrix Market vector of N entries, a row or a column). Names are checked against the
/// earlier outputs and the column names they would make.
Output read_output(const Reader& r, const toml::table& t, int index, int dofs, const std::vector<Output>& earlier) {
    const std::string where = "output[" + std::to_string(index + 1) + "]";
    r.only(t, config_keys_of("output[]"), where);
    const toml::node* dof = t.get("dof");
    const toml::node* row = t.get("row");
    const toml::node* name = t.get("name");
    if ((dof != nullptr) == (row != nullptr))
        fail(r.file, t.source(), where, "give exactly one of 'dof' (a DOF, 1-based) and 'row' (a row vector c: o = c^T y)");
    std::string label;
    if (name) {
        if (!name->is_string()) fail(r.file, name->source(), where + ".name", "expected a string");
        label = name->as_string()->get();
        const bool good = !label.empty() && label.size() <= 40 && std::isalpha(static_cast<unsigned char>(label[0])) &&
                          std::all_of(label.begin(), label.end(), [](char ch) {
                              return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_';
                          });
        if (!good)
            fail(r.file, name->source(), where + ".name",
                 "'" + label + "' is not allowed: a letter, then letters, digits or '_', at most 40 characters "
                 "(it names the CSV columns <name>_max and <name>_amp1)");
    } else if (row) {
        fail(r.file, t.source(), where + ".name", "missing: an output given by 'row' needs a name");
    }
    std::optional<Output> output;
    if (dof) {
        const int d = r.integer(*dof, where + ".dof");
        if (d < 1 || d > dofs)
            fail(r.file, dof->source(), where + ".dof",
                 std::to_string(d) + " is out of range: allowed 1.." + std::to_string(dofs) + " (1-based DOF)");
        output = Output::dof(d - 1);
        if (!label.empty()) output = Output(label, output->terms());
    } else {
        Eigen::VectorXd c;
        if (row->is_string()) {
            const SparseMatrix m = r.matrix(*row, where + ".row");
            if (m.rows() != 1 && m.cols() != 1)
                fail(r.file, row->source(), where + ".row",
                     "the Matrix Market file is " + std::to_string(m.rows()) + " x " + std::to_string(m.cols()) +
                         ": allowed a row or a column of " + std::to_string(dofs) + " entries");
            c = m.cols() == 1 ? Eigen::VectorXd(Eigen::MatrixXd(m).col(0)) : Eigen::VectorXd(Eigen::MatrixXd(m).row(0).transpose());
            if (c.size() != dofs)
                fail(r.file, row->source(), where + ".row",
                     std::to_string(c.size()) + " entries: allowed " + std::to_string(dofs) + " (the number of DOFs)");
        } else {
            c = r.vector(*row, where + ".row", dofs);
        }
        std::vector<Output::Term> terms;
        for (int i = 0; i < dofs; ++i) {
            if (!std::isfinite(c(i))) fail(r.file, row->source(), where + ".row", "entry " + std::to_string(i + 1) + " is not finite");
            if (c(i) != 0.0) terms.emplace_back(i, c(i));
        }
        if (terms.empty()) fail(r.file, row->source(), where + ".row", "every entry is zero: allowed a nonzero row");
        output = Output(label, terms);
    }
    // y<i> names belong to DOF i; stick_margin would collide with a time-integration column.
    const std::string& final_name = output->name();
    const bool dof_style = final_name.size() > 1 && final_name[0] == 'y' &&
                           std::all_of(final_name.begin() + 1, final_name.end(), [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)); });
    if (dof_style && !(output->single_dof() >= 0 && final_name == "y" + std::to_string(output->single_dof() + 1)))
        fail(r.file, (name ? name : &t)->source(), where + ".name",
             "'" + final_name + "' is reserved for DOF " + final_name.substr(1) + " (y<i> names DOF i)");
    if (final_name == "stick_margin" || final_name == "w")
        fail(r.file, (name ? name : &t)->source(), where + ".name",
             "'" + final_name + "' is reserved (its columns would collide with hbf's own)");
    for (const Output& o : earlier)
        if (o.name() == final_name)
            fail(r.file, (name ? name : &t)->source(), where + ".name",
                 "'" + final_name + "' is already an output name: allowed distinct names");
    return *output;
}

SystemConfig read_system_config(const std::string& path) {
    SystemConfig config;
    config.inputs.push_back({"--config", path});
    Reader r;
    r.file = path;
    r.inputs = &config.inputs;
    const auto slash = path.find_last_of('/');
    r.directory = slash == std::string::npos ? "" : path.substr(0, slash + 1);
    // A regular file of bounded size, read here and scanned before the parser sees it.
    std::error_code error;
    const auto status = std::filesystem::status(path, error);
    if (!std::filesystem::exists(status))
        throw InvalidInput("--config = '" + path + "' cannot be read (no such file, or not readable)");
    if (!std::filesystem::is_regular_file(status))
        throw InvalidInput("--config = '" + path + "' is not a regular file (a directory, device or FIFO): allowed a "
                           "TOML file");
    const std::uintmax_t bytes = std::filesystem::file_size(path, error);
    if (error || bytes > max_config_bytes)
        throw InvalidInput("--config = '" + path + "' has " + std::to_string(bytes) + " bytes: allowed at most " +
                           std::to_string(max_config_bytes) + " (64 MB; put large matrices in Matrix Market files)");
    std::string text;
    {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw InvalidInput("--config = '" + path + "' cannot be read (no such file, or not readable)");
        std::ostringstream buffer;
        buffer << in.rdbuf();
        text = buffer.str();
    }
    check_nesting(path, text);
    toml::table root;
    try {
        root = toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        fail(path, e.source(), "", "syntax error: " + std::string(e.description()));
    }
    r.only(root, config_keys_of(""), "");

    System& s = config.system;
    const toml::table* structure = root["structure"].as_table();
    if (!structure) fail(path, root.source(), "structure", "missing table [structure] (mass, stiffness, excitation)");
    r.only(*structure, config_keys_of("structure"), "structure");
    for (const char* key : {"mass", "stiffness", "excitation"})
        if (!structure->get(key)) fail(path, structure->source(), std::string("structure.") + key, "missing");
    s.mass = r.matrix(*structure->get("mass"), "structure.mass");
    const Eigen::Index n = s.mass.rows();
    s.stiffness = r.matrix(*structure->get("stiffness"), "structure.stiffness");
    s.damping = structure->get("damping") ? r.matrix(*structure->get("damping"), "structure.damping")
                                          : SparseMatrix(n, n);
    s.excitation = r.vector(*structure->get("excitation"), "structure.excitation", -1);
    if (const toml::node* load = structure->get("static_load"))
        s.static_load = r.vector(*load, "structure.static_load", n);
    if (const toml::node* h = structure->get("excitation_harmonic"))
        s.excitation_harmonic = r.integer(*h, "structure.excitation_harmonic");
    for (const auto& [key, m] : {std::pair<const char*, const SparseMatrix*>{"stiffness", &s.stiffness}, {"damping", &s.damping}})
        if (m->rows() != n)
            fail(path, structure->get(key) ? structure->get(key)->source() : structure->source(), std::string("structure.") + key,
                 std::to_string(m->rows()) + " x " + std::to_string(m->cols()) + ": allowed " + std::to_string(n) + " x " +
                     std::to_string(n) + " (the size of the mass matrix)");

    // [structure] fixed: clamped DOFs (taken out below, after the contacts and interfaces,
    // which like every other key use the file's numbering).
    std::vector<int> fixed;
    const toml::node* fixed_node = structure->get("fixed");
    if (fixed_node) fixed = r.dof_list(*fixed_node, "structure.fixed", static_cast<int>(n));
    const toml::table* cyclic = nullptr;
    if (const toml::node* node = root.get("cyclic")) {
        cyclic = node->as_table();
        if (!cyclic) fail(path, node->source(), "cyclic", "expected a table [cyclic]");
        read_cyclic(r, *cyclic, static_cast<int>(n), config);
    }
    std::vector<toml::source_region> contact_lines;
    std::vector<int> neighbours;  // per contact: the next sector's DOF it joins, or -1
    if (const toml::node* contacts = root.get("contact")) {
        const toml::array* list = contacts->as_array();
        if (!list || !list->is_array_of_tables()) fail(path, contacts->source(), "contact", "expected [[contact]] tables");
        int index = 0;
        for (const toml::node& node : *list) {
            int neighbour = -1;
            s.contacts.push_back(read_contact(r, *node.as_table(), index++, static_cast<int>(n), cyclic != nullptr, neighbour));
            neighbours.push_back(neighbour);
            contact_lines.push_back(node.source());
        }
    }
    if (cyclic) place_neighbours(neighbours, s);
    // [[interface]]: one contact per node, after the [[contact]] tables (on the reduced
    // coordinates when there is a [reduction]: config_fe.cpp).
    std::vector<ContactInterface> interfaces;
    std::vector<toml::source_region> interface_lines;
    if (const toml::node* node = root.get("interface")) {
        const toml::array* list = node->as_array();
        if (!list || !list->is_array_of_tables()) fail(path, node->source(), "interface", "expected [[interface]] tables");
        for (const toml::node& item : *list) {
            interfaces.push_back(detail::read_interface(r, *item.as_table(), static_cast<int>(interfaces.size()), static_cast<int>(n)));
            interface_lines.push_back(item.source());
        }
    }
    // Their preload pressures: static loads on the FE DOFs (before any reduction).
    for (const ContactInterface& iface : interfaces)
        if (iface.preload_pressure > 0.0) {
            if (s.static_load.size() != n) s.static_load = Eigen::VectorXd::Zero(n);
            s.static_load += interface_load(iface, static_cast<int>(n));
        }
    std::optional<ClampedSystem> clamped;
    if (fixed_node) {
        const std::set<int> clamped_dofs(fixed.begin(), fixed.end());
        for (std::size_t i = 0; i < interfaces.size(); ++i)
            for (std::size_t k = 0; k < interfaces[i].nodes.size(); ++k)
                for (int d : interfaces[i].nodes[k])
                    if (clamped_dofs.count(d))
                        fail(path, interface_lines[i], "interface[" + std::to_string(i + 1) + "].nodes",
                             "node " + std::to_string(k + 1) + "'s DOF " + std::to_string(d + 1) +
                                 " is clamped (structure.fixed): allowed free DOFs (a contact node must move)");
        try {
            clamped = clamp(s, fixed);
        } catch (const InvalidInput& e) {
            const std::string what = e.what();
            if (what.rfind("contact ", 0) == 0) {
                const std::size_t c = std::stoul(what.substr(8)) - 1;
                fail(path, c < contact_lines.size() ? contact_lines[c] : fixed_node->source(), "contact[" + std::to_string(c + 1) + "]", what);
            }
            const std::string prefix = "structure.fixed: ";
            fail(path, fixed_node->source(), "structure.fixed", what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
        }
        s = clamped->system;
    }
    // The file's DOF d is the model's index(d) (-1: clamped), the model's DOF i the file's user(i).
    const auto index = [&clamped](int d) { return clamped ? clamped->index[static_cast<std::size_t>(d)] : d; };
    const auto user = [&clamped](int i) { return clamped ? clamped->kept[static_cast<std::size_t>(i)] : i; };
    const bool reduced = root.get("reduction") != nullptr;
    std::vector<std::string> contact_keys;
    for (std::size_t c = 0; c < s.contacts.size(); ++c) contact_keys.push_back("contact[" + std::to_string(c + 1) + "]");
    if (!reduced)
        config.interfaces = detail::add_interface_contacts(path, interfaces, interface_lines, s, static_cast<int>(n),
                                                           s.dofs(), index, contact_keys, contact_lines);
    // Matrix properties and contact parameter ranges: System::validate names the item; the
    // file and line are added here.
    try {
        s.validate();
    } catch (const InvalidInput& e) {
        const std::string what = e.what();
        std::string key = "structure";
        toml::source_region where = structure->source();
        if (what.rfind("cyclic symmetry", 0) == 0 && cyclic) {
            key = "cyclic";
            where = cyclic->source();
        } else if (what.rfind("contact ", 0) == 0) {
            const std::size_t c = std::stoul(what.substr(8)) - 1;
            key = c < contact_keys.size() ? contact_keys[c] : "contact[" + std::to_string(c + 1) + "]";
            if (c < contact_lines.size()) where = contact_lines[c];
        } else {
            // (key, the word System::validate uses for it), the most specific first
            for (const auto& [k, word] : {std::pair<const char*, const char*>{"excitation_harmonic", "excitation harmonic"},
                                          {"static_load", "static load"},
                                          {"mass", "mass"}, {"damping", "damping"}, {"stiffness", "stiffness"},
                                          {"excitation", "excitation"}})
                if (what.find(word) != std::string::npos) {
                    key = std::string("structure.") + k;
                    if (const toml::node* node = structure->get(k)) where = node->source();
                    break;
                }
        }
        fail(path, where, key, what);
    }

    if (const toml::node* node = root.get("frequency")) {
        const toml::table* t = node->as_table();
        if (!t) fail(path, node->source(), "frequency", "expected a table [frequency]");
        r.only(*t, config_keys_of("frequency"), "frequency");
        for (auto&& [key, value] : *t) config.lines["frequency." + std::string(key.str())] = static_cast<int>(value.source().begin.line);
        if (const toml::node* v = t->get("wmin")) config.choices.omega_start = r.number(*v, "frequency.wmin");
        if (const toml::node* v = t->get("wmax")) config.choices.omega_end = r.number(*v, "frequency.wmax");
        if (config.choices.omega_start && !(*config.choices.omega_start > 0.0 && std::isfinite(*config.choices.omega_start)))
            fail(path, t->get("wmin")->source(), "frequency.wmin", format_number(*config.choices.omega_start) + " is out of range: allowed > 0");
        if (config.choices.omega_end && !(*config.choices.omega_end > 0.0 && std::isfinite(*config.choices.omega_end)))
            fail(path, t->get("wmax")->source(), "frequency.wmax", format_number(*config.choices.omega_end) + " is out of range: allowed > 0");
        if (config.choices.omega_start && config.choices.omega_end && !(*config.choices.omega_end >= *config.choices.omega_start))
            fail(path, t->get("wmax")->source(), "frequency.wmax",
                 "must exceed wmin = " + format_number(*config.choices.omega_start) + " (or equal it: one point)");
    }
    if (const toml::node* node = root.get("solver")) {
        const toml::table* t = node->as_table();
        if (!t) fail(path, node->source(), "solver", "expected a table [solver]");
        r.only(*t, config_keys_of("solver"), "solver");
        for (auto&& [key, value] : *t) config.lines["solver." + std::string(key.str())] = static_cast<int>(value.source().begin.line);
        if (const toml::node* v = t->get("odd_harmonics")) {
            const auto flag = v->as_boolean();
            if (!flag) fail(path, v->source(), "solver.odd_harmonics", "expected true or false");
            config.choices.odd_harmonics = flag->get();
        }
        if (const toml::node* v = t->get("jacobian")) {
            const auto text = v->as_string();
            if (!text) fail(path, v->source(), "solver.jacobian", "expected a string: automatic, dense or structured");
            try {
                config.choices.jacobian = parse_jacobian_form(text->get());
            } catch (const InvalidInput& e) {
                fail(path, v->source(), "solver.jacobian", e.what());
            }
        }
        // The ranges are the library's (HarmonicBalanceOptions::validate): checked here where the
        // value alone decides (H, modes), with the line; N_t against H once H is chosen
        // (FrfSettings::validate).
        const auto check = [&](const toml::node& v, const std::string& key, const HarmonicBalanceOptions& o) {
            try {
                o.validate();
            } catch (const InvalidInput& e) {
                const std::string what = e.what();
                const std::size_t equals = what.find(" = ");
                fail(path, v.source(), key, equals == std::string::npos ? what : what.substr(equals + 3));
            }
        };
        if (const toml::node* v = t->get("modes")) {
            config.choices.modes = r.integer(*v, "solver.modes");
            HarmonicBalanceOptions o;
            o.modes = *config.choices.modes;
            check(*v, "solver.modes", o);
        }
        if (const toml::node* v = t->get("harmonics")) {
            config.choices.harmonics = r.integer(*v, "solver.harmonics");
            HarmonicBalanceOptions o;
            o.harmonics = *config.choices.harmonics;
            check(*v, "solver.harmonics", o);
        }
        if (const toml::node* v = t->get("time_samples")) config.choices.time_samples = r.integer(*v, "solver.time_samples");
    }
    if (const toml::node* node = root.get("output")) {
        if (const toml::array* list = node->as_array()) {  // [[output]] tables
            if (list->empty()) fail(path, node->source(), "output", "expected at least one [[output]] table");
            for (std::size_t k = 0; k < list->size(); ++k) {
                const toml::table* t = list->get(k)->as_table();
                if (!t) fail(path, list->get(k)->source(), "output", "expected [[output]] tables");
                config.outputs.push_back(read_output(r, *t, static_cast<int>(k), n, config.outputs));
            }
        } else {
            const toml::table* t = node->as_table();
            if (!t) fail(path, node->source(), "output", "expected a table [output] or tables [[output]]");
            r.only(*t, config_keys_of("output"), "output");
            if (const toml::node* v = t->get("report")) {
                const toml::array* a = v->as_array();
                if (!a || a->empty()) fail(path, v->source(), "output.report", "expected a non-empty list of DOFs (1-based)");
                for (const toml::node& item : *a) {
                    const int d = r.integer(item, "output.report");
                    if (d < 1 || d > n)
                        fail(path, item.source(), "output.report",
                             std::to_string(d) + " is out of range: allowed 1.." + std::to_string(n) + " (1-based DOF)");
                    for (const Output& o : config.outputs)
                        if (o.single_dof() == d - 1)
                            fail(path, item.source(), "output.report", "DOF " + std::to_string(d) + " is listed twice");
                    config.outputs.push_back(Output::dof(d - 1));
                }
            }
        }
    }
    if (config.outputs.empty()) {
        // The excited DOFs and those of the contacts: every DOF of a large model would make
        // the run as slow as its output count (each is synthesised in time at every point).
        // (In the file's numbering: the model's DOF i is the file's user(i).)
        const Eigen::Index m = s.dofs();
        std::set<int> dofs;
        for (Eigen::Index i = 0; i < m; ++i)
            if (s.excitation(i) != 0.0) dofs.insert(user(static_cast<int>(i)));
        for (const Contact& c : s.contacts) {
            // (the force elements over several coordinates: each of them; of a sector, its own
            // DOFs, not the next sector's added for a contact across the cut)
            const Eigen::MatrixXd w = contact_law(c.law).friction() ? Eigen::MatrixXd(s.contact_direction(c))
                                                                    : s.contact_directions(c);
            for (Eigen::Index i = 0; i < m && i < w.rows(); ++i)
                if (w.row(i).cwiseAbs().maxCoeff() != 0.0) dofs.insert(user(static_cast<int>(i)));
        }
        if (dofs.empty())
            for (int i = 0; i < m; ++i) dofs.insert(user(i));
        for (int i : dofs) config.outputs.push_back(Output::dof(i));
        if (static_cast<Eigen::Index>(dofs.size()) < m) {
            std::string list;
            for (int i : dofs) list += (list.empty() ? "" : ", ") + std::to_string(i + 1);
            config.outputs_note = path + ": no [output]: reporting the excited and contact DOFs " + list + " of " +
                                  std::to_string(n) + " ([output] report = [...] or [[output]] rows choose others)";
        }
    }
    // The outputs (in the file's numbering) on the clamped model; with a reduction they stay in
    // the file's numbering, the reduced model being given in it.
    if (clamped) {
        try {
            std::vector<Output> outputs = clamped_outputs(config.outputs, *clamped);
            if (!reduced) config.outputs = std::move(outputs);
        } catch (const InvalidInput& e) {
            const toml::node* node = root.get("output");
            fail(path, node ? node->source() : fixed_node->source(), node ? "output" : "structure.fixed", e.what());
        }
    }
    if (const toml::node* node = root.get("reduction"))
        detail::read_reduction(r, *node, config, contact_lines, interfaces, interface_lines, clamped ? &*clamped : nullptr);
    return config;
}

}  // namespace hbf::io
