// hbfriction — reading system files (config.hpp), the parts shared by its sources: the reading
// context and the error form "FILE:LINE: key 'K': what". Private to src/config*.cpp.
#pragma once

#include <toml++/toml.h>

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/error.hpp"
#include "hbf/interface.hpp"
#include "hbf/model.hpp"
#include "hbf/reduction.hpp"

namespace hbf::io::detail {

/// Throws InvalidInput "FILE:LINE: key 'K': what".
[[noreturn]] inline void fail(const std::string& file, const toml::source_region& where, const std::string& key,
                       const std::string& what) {
    std::string message = file;
    if (where.begin.line > 0) message += ":" + std::to_string(where.begin.line);
    message += ": ";
    if (!key.empty()) message += "key '" + key + "': ";
    throw InvalidInput(message + what);
}

/// Reading context of one file: its path (for messages) and directory (for .mtx files).
struct Reader {
    std::string file, directory;
    std::vector<InputFile>* inputs = nullptr;  ///< every Matrix Market file read is added

    double number(const toml::node& node, const std::string& key) const {
        if (auto v = node.as_floating_point()) return v->get();
        if (auto v = node.as_integer()) return static_cast<double>(v->get());
        fail(file, node.source(), key, "expected a number");
    }

    int integer(const toml::node& node, const std::string& key) const {
        if (auto v = node.as_integer()) {
            const auto value = v->get();
            if (value < -1000000000LL || value > 1000000000LL) fail(file, node.source(), key, "integer out of range");
            return static_cast<int>(value);
        }
        fail(file, node.source(), key, "expected an integer");
    }

    std::vector<double> list(const toml::node& node, const std::string& key) const {
        const toml::array* a = node.as_array();
        if (!a) fail(file, node.source(), key, "expected a list of numbers");
        std::vector<double> values;
        for (const toml::node& item : *a) values.push_back(number(item, key));
        return values;
    }

    /// A matrix: rows [[...], [...]], a flat list (diagonal), or a Matrix Market file name.
    SparseMatrix matrix(const toml::node& node, const std::string& key) const {
        if (auto name = node.as_string()) {
            const std::string path = name->get().empty() || name->get().front() == '/' ? name->get()
                                                                                       : directory + name->get();
            if (inputs) inputs->push_back({key, path});
            try {
                return read_matrix_market(path);
            } catch (const InvalidInput& e) {
                fail(file, node.source(), key, e.what());
            }
        }
        const toml::array* a = node.as_array();
        if (!a || a->empty()) fail(file, node.source(), key, "expected a matrix: rows [[..], ..], a diagonal [..] or a file name");
        if (!a->front().is_array()) {
            const std::vector<double> d = list(node, key);
            return sparse(Eigen::Map<const Eigen::VectorXd>(d.data(), static_cast<Eigen::Index>(d.size())).asDiagonal());
        }
        const auto n = static_cast<Eigen::Index>(a->size());
        Eigen::MatrixXd m(n, n);
        for (Eigen::Index i = 0; i < n; ++i) {
            const toml::node& row_node = *a->get(static_cast<std::size_t>(i));
            const std::vector<double> row = list(row_node, key);
            if (static_cast<Eigen::Index>(row.size()) != n)
                fail(file, row_node.source(), key,
                     "row " + std::to_string(i + 1) + " has " + std::to_string(row.size()) + " entries: allowed " +
                         std::to_string(n) + " (a square matrix)");
            for (Eigen::Index j = 0; j < n; ++j) m(i, j) = row[static_cast<std::size_t>(j)];
        }
        return sparse(m);
    }

    /// A vector of n entries: a list of numbers, or a Matrix Market file of one column.
    Eigen::VectorXd vector(const toml::node& node, const std::string& key, Eigen::Index n) const {
        Eigen::VectorXd v;
        if (node.is_string()) {
            const SparseMatrix m = matrix(node, key);
            if (m.cols() != 1) fail(file, node.source(), key, "the Matrix Market file has " + std::to_string(m.cols()) +
                                                                  " columns: allowed 1 (a vector)");
            v = Eigen::MatrixXd(m).col(0);
        } else {
            const std::vector<double> d = list(node, key);
            v = Eigen::Map<const Eigen::VectorXd>(d.data(), static_cast<Eigen::Index>(d.size()));
        }
        if (n >= 0 && v.size() != n)
            fail(file, node.source(), key, std::to_string(v.size()) + " entries: allowed " + std::to_string(n) +
                                               " (the number of DOFs)");
        return v;
    }

    /// A list of 1-based DOFs (a list of integers or a Matrix Market file of one column), as
    /// 0-based DOFs: each an integer in 1..n, none twice, at least one.
    std::vector<int> dof_list(const toml::node& node, const std::string& key, int n) const {
        const Eigen::VectorXd list = vector(node, key, -1);
        if (list.size() == 0) fail(file, node.source(), key, "empty: allowed a list of 1-based DOFs");
        std::vector<int> dofs;
        std::set<int> seen;
        for (Eigen::Index k = 0; k < list.size(); ++k) {
            const double d = list(k);
            if (!(d == std::floor(d)) || std::abs(d) > 1e9)
                fail(file, node.source(), key,
                     "entry " + std::to_string(k + 1) + " = " + format_number(d) + " is not a DOF: allowed integers 1.." + std::to_string(n));
            if (d < 1 || d > n)
                fail(file, node.source(), key,
                     "DOF " + format_number(d) + " (entry " + std::to_string(k + 1) + ") is out of range: allowed 1.." + std::to_string(n));
            if (!seen.insert(static_cast<int>(d)).second)
                fail(file, node.source(), key, "DOF " + std::to_string(static_cast<int>(d)) + " is listed twice");
            dofs.push_back(static_cast<int>(d) - 1);
        }
        return dofs;
    }

    /// A table of rows: rows [[...], [...]] of equal width, one row [...], or a Matrix Market
    /// file (dense or coordinate).
    Eigen::MatrixXd rows(const toml::node& v, const std::string& key) const {
        Eigen::MatrixXd m;
        if (v.is_string()) {
            m = Eigen::MatrixXd(matrix(v, key));
        } else if (const toml::array* a = v.as_array(); a && !a->empty() && a->front().is_array()) {
            for (std::size_t i = 0; i < a->size(); ++i) {
                const std::vector<double> row = list(*a->get(i), key);
                if (i == 0) m.resize(static_cast<Eigen::Index>(a->size()), static_cast<Eigen::Index>(row.size()));
                if (static_cast<Eigen::Index>(row.size()) != m.cols())
                    fail(file, a->get(i)->source(), key, "row " + std::to_string(i + 1) + " has " + std::to_string(row.size()) +
                                                            " entries: allowed " + std::to_string(m.cols()) + " as row 1");
                for (std::size_t j = 0; j < row.size(); ++j) m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = row[j];
            }
        } else {
            const std::vector<double> row = list(v, key);
            m = Eigen::Map<const Eigen::MatrixXd>(row.data(), 1, static_cast<Eigen::Index>(row.size()));
        }
        return m;
    }

    /// Rejects keys of `table` outside `allowed`, naming the table.
    void only(const toml::table& table, const std::set<std::string>& allowed, const std::string& where) const {
        for (auto&& [key, node] : table) {
            if (allowed.count(std::string(key.str())) == 0) {
                std::string list;
                for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
                fail(file, key.source(), where.empty() ? std::string(key.str()) : where + "." + std::string(key.str()),
                     "unknown key: allowed " + list);
            }
        }
    }
};

/// [reduction] (config_fe.cpp): reduces config.system (the FE model with its [[contact]]s),
/// adds the interfaces' contacts on the reduced coordinates (their nodes' DOFs are retained by
/// default) and carries the outputs; the lines locate each table for messages. With `clamped`
/// (structure.fixed), config.system is the clamped model, while the interfaces, the outputs and
/// reduction.interface use the file's numbering: the reduced model is given in it (unclamped).
void read_reduction(const Reader& r, const toml::node& node, SystemConfig& config,
                    const std::vector<toml::source_region>& contact_lines,
                    const std::vector<ContactInterface>& interfaces,
                    const std::vector<toml::source_region>& interface_lines, const ClampedSystem* clamped);

/// One [[interface]] table (config_fe.cpp; interface.hpp), validated against `dofs` FE DOFs.
ContactInterface read_interface(const Reader& r, const toml::table& t, int index, int dofs);

/// Appends every interface's contacts (on `coordinates` coordinates, coordinate(dof) mapping
/// FE DOFs) to system.contacts, with their keys ("interface[2] node 5") and lines for messages;
/// returns where each interface's contacts are.
std::vector<InterfaceContacts> add_interface_contacts(const std::string& path, const std::vector<ContactInterface>& interfaces,
                            const std::vector<toml::source_region>& interface_lines, System& system, int dofs,
                            int coordinates, const std::function<int(int)>& coordinate,
                            std::vector<std::string>& contact_keys, std::vector<toml::source_region>& contact_lines);

}  // namespace hbf::io::detail
