// Bench records: JSON lines between processes, CSV/JSON files for plots.
#include "cli/bench_records.hpp"

#include "engine/error.hpp"

#include <cmath>
#include <cstdio>
#include <map>

namespace hemirad {

void BenchRecord::set(const std::string& key, double value) {
    char text[64];
    if (!std::isfinite(value)) std::snprintf(text, sizeof text, "null");
    else std::snprintf(text, sizeof text, "%.9g", value);
    m_fields.emplace_back(key, text);
}

void BenchRecord::set(const std::string& key, const std::string& value) {
    std::string quoted = "\"";
    for (char c : value) {
        if (c == '"' || c == '\\') quoted += '\\';
        quoted += c;
    }
    m_fields.emplace_back(key, quoted + "\"");
}

std::string BenchRecord::json() const {
    std::string out = "{";
    for (std::size_t k = 0; k < m_fields.size(); ++k)
        out += (k ? ", \"" : "\"") + m_fields[k].first + "\": " + m_fields[k].second;
    return out + "}";
}

BenchRecord BenchRecord::parse(const std::string& line) {
    BenchRecord r;
    std::size_t i = line.find('{');
    if (i == std::string::npos) throw Error("bench: child output is not a JSON object: " + line);
    ++i;
    auto skip = [&] {
        while (i < line.size() && (line[i] == ' ' || line[i] == ',')) ++i;
    };
    auto string = [&] {
        std::string s = "\"";
        ++i;
        while (i < line.size() && line[i] != '"') {
            if (line[i] == '\\' && i + 1 < line.size()) s += line[i++];
            s += line[i++];
        }
        ++i;
        return s + "\"";
    };
    for (;;) {
        skip();
        if (i >= line.size() || line[i] == '}') break;
        if (line[i] != '"') throw Error("bench: malformed child output: " + line);
        std::string key = string();
        key = key.substr(1, key.size() - 2);
        skip();
        if (i >= line.size() || line[i] != ':') throw Error("bench: malformed child output: " + line);
        ++i;
        skip();
        std::string value;
        if (i < line.size() && line[i] == '"') {
            value = string();
        } else {
            const std::size_t start = i;
            while (i < line.size() && line[i] != ',' && line[i] != '}') ++i;
            value = line.substr(start, i - start);
            while (!value.empty() && value.back() == ' ') value.pop_back();
        }
        r.m_fields.emplace_back(key, value);
    }
    return r;
}

std::string toCsv(const std::vector<BenchRecord>& records) {
    std::vector<std::string> keys;
    std::map<std::string, bool> seen;
    for (const BenchRecord& r : records)
        for (const auto& [key, value] : r.fields())
            if (!seen[key]) {
                seen[key] = true;
                keys.push_back(key);
            }
    std::string out;
    for (std::size_t k = 0; k < keys.size(); ++k) out += (k ? "," : "") + keys[k];
    out += '\n';
    for (const BenchRecord& r : records) {
        std::map<std::string, std::string> values(r.fields().begin(), r.fields().end());
        for (std::size_t k = 0; k < keys.size(); ++k) {
            std::string v = values.count(keys[k]) ? values[keys[k]] : "";
            if (v == "null") v.clear();
            if (v.size() >= 2 && v.front() == '"') v = v.substr(1, v.size() - 2);
            out += (k ? "," : "") + v;
        }
        out += '\n';
    }
    return out;
}

std::string toJsonArray(const std::vector<BenchRecord>& records) {
    std::string out = "[\n";
    for (std::size_t k = 0; k < records.size(); ++k) out += "  " + records[k].json() + (k + 1 < records.size() ? ",\n" : "\n");
    return out + "]\n";
}

}  // namespace hemirad
