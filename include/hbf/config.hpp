// hbfriction — general systems from a TOML file (`hbf frf --config system.toml`).
//
// A system file describes any N-DOF structure M y'' + C y' + K y + sum_c w_c f_c = F_s +
// F cos(h w t) (model.hpp) in any consistent units: [structure] (M, C, K, F, F_s), [[contact]]
// tables (a law and its parameters, contact_law.hpp), [[interface]] tables (meshed interfaces,
// interface.hpp), [frequency], [solver], [output] or [[output]], and [reduction] (an FE model
// reduced onto its interface, reduction.hpp). Every key is listed with its meaning by
// config_keys() below, from which the reader checks the files and the documentation's
// system-file reference is generated (`hbf reference`). Unknown keys and tables, and contact
// keys that do not apply to the contact's law, are rejected: a misspelt key is an error, not a
// silent default. Every error names the file, the line and the key.
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "hbf/frf.hpp"
#include "hbf/interface.hpp"
#include "hbf/model.hpp"
#include "hbf/output_file.hpp"
#include "hbf/reduction.hpp"

namespace hbf::io {

struct SystemConfig {
    System system;
    /// [frequency] wmin, wmax (omega_start, omega_end) and [solver] harmonics, time_samples,
    /// modes, odd_harmonics, jacobian as given, each unset where not: the FRF's choices
    /// (frf.hpp: frf_settings), for hbf and Python alike.
    FrfChoices choices;
    /// The reported outputs in file order: [output] report's DOFs, or the [[output]] tables;
    /// default the excited DOFs and those of the contacts, in DOF order (every DOF when there
    /// are none), with outputs_note saying so when that leaves DOFs out.
    std::vector<Output> outputs;
    std::string outputs_note;
    /// [cyclic] engine_order outside 0..N-1: which engine order it was taken as (a note).
    std::string cyclic_note;
    /// The files read: the config itself ("--config"), then every Matrix Market file it names
    /// (by its key, e.g. "structure.stiffness").
    std::vector<InputFile> inputs;
    /// The line of each [frequency] and [solver] key given ("solver.time_samples" -> 12), for
    /// front ends whose checks depend on other settings (time_samples > 2H) to name it.
    std::map<std::string, int> lines;
    /// [reduction]: the FE model's reduction (system is then the reduced one; outputs are
    /// rows of its recovery matrix); null without [reduction].
    std::shared_ptr<const ReducedModel> reduction;
    /// The [[interface]] tables' contacts in system.contacts (after the [[contact]] tables').
    std::vector<InterfaceContacts> interfaces;
};

/// One key of a system file: its table ("structure"; "output[]" for the [[output]] tables, ""
/// for the top level, whose keys are the tables), its name and its meaning. The contact and
/// interface tables also take their law's parameters (ContactLaw::parameters()).
struct ConfigKey {
    const char* table;
    const char* key;
    const char* meaning;
};
/// Every key a system file may have outside the laws' parameters, table by table.
const std::vector<ConfigKey>& config_keys();
/// The keys of `table` (config_keys); throws std::logic_error for a table it does not know.
std::set<std::string> config_keys_of(const std::string& table);

/// Reads and validates a system file (see above). Throws InvalidInput with
/// "FILE:LINE: key 'K': ..." on any error (syntax, type, size, range, unknown key).
SystemConfig read_system_config(const std::string& path);

/// Reads a Matrix Market file ("%%MatrixMarket matrix coordinate|array real|integer
/// general|symmetric") as a sparse matrix (a coordinate file is never densified; a symmetric
/// file gives one triangle, mirrored). Every field is read whole: indices are integers, values
/// decimal numbers with an optional e, E, d or D exponent (hbf::parse_decimal: 1.0D-1 = 0.1
/// as Fortran prints it; a decimal comma, hexadecimal or trailing characters are refused);
/// the size line has exactly 3 fields (coordinate) or 2 (array), an entry line exactly 3 or
/// 1. Throws InvalidInput naming the file, line and field on any error: syntax, a field that
/// is not a number, a non-finite value, an index out of range, an entry given twice, data
/// beyond the announced entries.
SparseMatrix read_matrix_market(const std::string& path);

}  // namespace hbf::io
