// One benchmark measurement as flat key/value fields, written as JSON lines and CSV rows.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace hemirad {

/// Ordered fields of one run; values are numbers or strings (strings are quoted in JSON).
class BenchRecord {
public:
    void set(const std::string& key, double value);
    void set(const std::string& key, const std::string& value);
    const std::vector<std::pair<std::string, std::string>>& fields() const { return m_fields; }
    std::string json() const;
    /// Parses a line written by json() (flat object of numbers and strings). Throws hemirad::Error.
    static BenchRecord parse(const std::string& line);

private:
    std::vector<std::pair<std::string, std::string>> m_fields;  // value text; strings keep their quotes
};

/// Writes records as CSV (header = the union of keys in first-seen order) and as a JSON array.
std::string toCsv(const std::vector<BenchRecord>& records);
std::string toJsonArray(const std::vector<BenchRecord>& records);

}  // namespace hemirad
