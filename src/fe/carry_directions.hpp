// hbfriction — a contact's direction parameters carried to other coordinates (reduction.cpp's
// reduced coordinates, clamp.cpp's free DOFs): one loop for both.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/model.hpp"

namespace hbf::detail {

/// Replaces each of `contact`'s law direction parameters (LawParameter::Kind::direction lists
/// and direction_rows tables, `n` entries each) by carry(its vector, its key), `size` entries.
/// Throws InvalidInput naming contact `index` (0-based) for a parameter of another length.
inline void carry_law_directions(Contact& contact, std::size_t index, int n, int size,
                                 const std::function<Eigen::VectorXd(const Eigen::VectorXd&, const std::string&)>& carry) {
    const std::string name = "contact " + std::to_string(index + 1);
    for (const LawParameter& p : contact_law(contact.law).parameters()) {
        if (p.kind == LawParameter::Kind::direction)
            if (auto at = contact.lists.find(p.key); at != contact.lists.end()) {
                if (static_cast<int>(at->second.size()) != n)
                    throw InvalidInput(name + ": " + p.key + " has " + std::to_string(at->second.size()) +
                                       " entries: allowed " + std::to_string(n));
                const Eigen::VectorXd w = carry(Eigen::Map<const Eigen::VectorXd>(at->second.data(), n), p.key);
                at->second.assign(w.data(), w.data() + w.size());
            }
        if (p.kind == LawParameter::Kind::direction_rows)
            if (auto at = contact.tables.find(p.key); at != contact.tables.end()) {
                if (static_cast<int>(at->second.cols()) != n)
                    throw InvalidInput(name + ": " + p.key + " has rows of " + std::to_string(at->second.cols()) +
                                       " entries: allowed " + std::to_string(n));
                Eigen::MatrixXd carried(at->second.rows(), size);
                for (Eigen::Index r = 0; r < carried.rows(); ++r)
                    carried.row(r) = carry(at->second.row(r).transpose(), p.key).transpose();
                at->second = carried;
            }
    }
}

}  // namespace hbf::detail
