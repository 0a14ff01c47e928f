// hbfriction — the Matrix Market reader (config.hpp: read_matrix_market), for the matrices a
// system file names.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "hbf/config.hpp"
#include "hbf/error.hpp"

namespace hbf::io {

SparseMatrix read_matrix_market(const std::string& path) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
        throw InvalidInput("Matrix Market file '" + path + "' is not a regular file (missing, a directory or a device)");
    std::ifstream in(path);
    if (!in) throw InvalidInput("Matrix Market file '" + path + "' cannot be read");
    auto bad = [&](int line, const std::string& what) -> InvalidInput {
        return InvalidInput(path + ":" + std::to_string(line) + ": " + what);
    };
    std::string line;
    int number = 0;
    if (!std::getline(in, line)) throw bad(1, "empty file");
    ++number;
    std::istringstream header(line);
    std::string banner, object, format, field, symmetry, extra;
    header >> banner >> object >> format >> field >> symmetry >> extra;
    for (std::string* word : {&object, &format, &field, &symmetry})
        for (char& ch : *word) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (banner != "%%MatrixMarket" || object != "matrix" || (format != "coordinate" && format != "array") ||
        (field != "real" && field != "integer") || (symmetry != "general" && symmetry != "symmetric") || !extra.empty())
        throw bad(number, "expected '%%MatrixMarket matrix coordinate|array real|integer general|symmetric'");
    // Every later line that is not blank or a comment, split at whitespace; every field must be
    // a whole number (parse_decimal, parse_whole_number) and every line has exactly its fields.
    std::vector<std::string> fields;
    auto next = [&]() {
        while (std::getline(in, line)) {
            ++number;
            if (!line.empty() && line.back() == '\r') line.pop_back();  // a file written on Windows
            fields.clear();
            std::istringstream words(line);
            for (std::string word; words >> word;) fields.push_back(word);
            if (fields.empty() || line[0] == '%') continue;
            return true;
        }
        return false;
    };
    const bool integer_field = field == "integer";
    auto field_name = [](std::size_t k, const char* what) { return "field " + std::to_string(k + 1) + " (" + what + ")"; };
    auto index = [&](std::size_t k, const char* what) {
        long long value = 0;
        std::string why;
        if (!parse_whole_number(fields[k], value, why))
            throw bad(number, field_name(k, what) + " = '" + fields[k] + "' " + why);
        return value;
    };
    auto value_of = [&](std::size_t k) {
        double value = 0.0;
        std::string why;
        if (integer_field) {
            long long whole = 0;
            if (!parse_whole_number(fields[k], whole, why))
                throw bad(number, field_name(k, "value") + " = '" + fields[k] + "' " + why + " (the file's field is integer)");
            return static_cast<double>(whole);
        }
        if (!parse_decimal(fields[k], value, why)) throw bad(number, field_name(k, "value") + " = '" + fields[k] + "' " + why);
        return value;
    };
    auto count = [&](std::size_t expected, const std::string& what) {
        if (fields.size() != expected)
            throw bad(number, std::to_string(fields.size()) + " fields: expected " + std::to_string(expected) + ", " + what);
    };
    const bool coordinate = format == "coordinate";
    if (!next()) throw bad(number, std::string("expected the size line '") + (coordinate ? "rows cols entries" : "rows cols") + "'");
    count(coordinate ? 3 : 2, coordinate ? "the size line 'rows cols entries'" : "the size line 'rows cols' (array format)");
    const long long rows = index(0, "rows"), cols = index(1, "cols"), entries = coordinate ? index(2, "entries") : 0;
    if (rows < 1 || cols < 1) throw bad(number, "size " + std::to_string(rows) + " x " + std::to_string(cols) + ": allowed at least 1 x 1");
    constexpr long long max_dimension = 1000000;
    if (rows > max_dimension || cols > max_dimension)
        throw bad(number, "size " + std::to_string(rows) + " x " + std::to_string(cols) +
                              " is out of range: allowed at most " + std::to_string(max_dimension) + " rows and columns");
    const bool symmetric = symmetry == "symmetric";
    // A symmetric file stores one triangle and is mirrored: only a square matrix can be (found
    // by fuzzing: a 3 x 2 symmetric file wrote past the matrix).
    if (symmetric && rows != cols)
        throw bad(number, "a symmetric matrix of size " + std::to_string(rows) + " x " + std::to_string(cols) +
                              ": allowed square (rows = cols)");
    std::vector<Eigen::Triplet<double>> triplets;
    auto add = [&](long long i, long long j, double v) {
        if (v == 0.0) return;
        triplets.emplace_back(static_cast<int>(i), static_cast<int>(j), v);
        if (symmetric && i != j) triplets.emplace_back(static_cast<int>(j), static_cast<int>(i), v);
    };
    if (coordinate) {
        constexpr long long max_entries = 100000000;
        if (entries < 0 || entries > rows * cols || entries > max_entries)
            throw bad(number, "entries = " + std::to_string(entries) + " is out of range: allowed 0..rows*cols, at most " +
                                  std::to_string(max_entries));
        // Reserved up to a bound: the count is only a promise until the entries are read.
        triplets.reserve(static_cast<std::size_t>(std::min(symmetric ? 2 * entries : entries, 1LL << 20)));
        std::set<std::pair<long long, long long>> seen;
        for (long long k = 0; k < entries; ++k) {
            if (!next()) throw bad(number, "the file ends before entry " + std::to_string(k + 1) + " of " + std::to_string(entries));
            count(3, "entry " + std::to_string(k + 1) + " 'row col value'");
            const long long i = index(0, "row"), j = index(1, "col");
            const double v = value_of(2);
            if (i < 1 || i > rows || j < 1 || j > cols)
                throw bad(number, "entry (" + std::to_string(i) + ", " + std::to_string(j) + "): index out of range: allowed row 1.." +
                                      std::to_string(rows) + ", col 1.." + std::to_string(cols));
            const auto key = symmetric ? std::make_pair(std::min(i, j), std::max(i, j)) : std::make_pair(i, j);
            if (!seen.insert(key).second)
                throw bad(number, "entry (" + std::to_string(i) + ", " + std::to_string(j) + ") given twice" +
                                      (symmetric ? " (a symmetric file stores one triangle)" : ""));
            add(i - 1, j - 1, v);
        }
    } else {
        if (rows * cols > 25000000LL) throw bad(number, "an array (dense) file larger than 25e6 entries: use the coordinate format");
        for (long long j = 0; j < cols; ++j)
            for (long long i = symmetric ? j : 0; i < rows; ++i) {
                if (!next()) throw bad(number, "the file ends before the value of (" + std::to_string(i + 1) + ", " +
                                                   std::to_string(j + 1) + ") (column-major)");
                count(1, "one value per line (array format, column-major)");
                add(i, j, value_of(0));
            }
    }
    if (next()) throw bad(number, "more data than the size line announces");
    SparseMatrix m(rows, cols);
    m.setFromTriplets(triplets.begin(), triplets.end());
    return m;
}

}  // namespace hbf::io
