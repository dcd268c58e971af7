// hemirad::Error, the one exception type of the project, with an optional file:line location.
#pragma once

#include <stdexcept>
#include <string>

namespace hemirad {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
    /// A message about a place in an input file; what() reads "file:line: message" (line 0: "file: message").
    Error(const std::string& file, int line, const std::string& message)
        : std::runtime_error(locate(file, line) + message), m_file(file), m_line(line) {}

    const std::string& file() const { return m_file; }
    int line() const { return m_line; }

    static std::string locate(const std::string& file, int line) {
        if (file.empty()) return {};
        return line > 0 ? file + ":" + std::to_string(line) + ": " : file + ": ";
    }

private:
    std::string m_file;
    int m_line = 0;
};

}  // namespace hemirad
