// CSV fields as RFC 4180 has them: quoted when they hold a comma, a quote or a line break, inner
// quotes doubled. Every CSV writer of the project names objects through it.
#pragma once

#include <string>

namespace hemirad {

inline std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

}  // namespace hemirad
