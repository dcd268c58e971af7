// Line-by-line tokenising reader for text formats (OBJ, MTL, Matrix Market) with checked number parsing.
#pragma once

#include "engine/error.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace hemirad {

class TextReader {
public:
    /// `text` must outlive the reader; `file` names it in errors.
    TextReader(std::string file, std::string_view text) : m_file(std::move(file)), m_text(text) {}

    /// Advances to the next line (joining '\'-continued lines, dropping '\r'); false at the end.
    bool next();
    int line() const { return m_line; }
    const std::string& file() const { return m_file; }
    /// The current line, and its whitespace-separated tokens.
    std::string_view text() const { return m_current; }
    const std::vector<std::string_view>& tokens() const { return m_tokens; }

    /// Throws hemirad::Error at the current line.
    [[noreturn]] void fail(const std::string& message) const { throw Error(m_file, m_line, message); }

    /// Token k parsed as a finite double / an integer; errors quote the token and say what it is.
    double number(std::size_t k, const char* what) const;
    long integer(std::size_t k, const char* what) const;
    /// Tokens from k to the end joined by single spaces (names with spaces).
    std::string rest(std::size_t k) const;

private:
    std::string m_file;
    std::string_view m_text;
    std::size_t m_pos = 0;
    int m_line = 0;
    int m_nextLine = 1;
    std::string m_joined;
    std::string_view m_current;
    std::vector<std::string_view> m_tokens;
};

/// Quotes a token for a message, shortening long or binary ones.
std::string quote(std::string_view token);

}  // namespace hemirad
