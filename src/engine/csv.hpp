// CSV fields as RFC 4180 has them: quoted when they hold a comma, a quote or a line break, inner
// quotes doubled. Every CSV writer of the project names objects through it.
#pragma once

#include <string>
#include <vector>

namespace hemirad {

inline std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

/// The fields of a line split at every comma (no quoting: the numeric tables Hemirad reads), as
/// they stand.
inline std::vector<std::string> splitCsvLine(const std::string& line) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = line.find(',', start);
        out.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

/// The fields of a line as csvField writes them: a quoted field unquoted (inner quotes undoubled),
/// commas inside quotes kept. `ok` is false for a quote left open or text after a closing quote.
inline std::vector<std::string> splitQuotedCsvLine(const std::string& line, bool& ok) {
    std::vector<std::string> out(1);
    ok = true;
    bool quoted = false, closed = false;
    for (std::size_t k = 0; k < line.size(); ++k) {
        const char c = line[k];
        if (quoted) {
            if (c != '"') out.back() += c;
            else if (k + 1 < line.size() && line[k + 1] == '"') out.back() += '"', ++k;
            else quoted = false, closed = true;
        } else if (c == ',') {
            out.emplace_back();
            closed = false;
        } else if (closed) {
            ok = false;
        } else if (c == '"' && out.back().empty()) {
            quoted = true;
        } else {
            out.back() += c;
        }
    }
    if (quoted) ok = false;
    return out;
}

}  // namespace hemirad
