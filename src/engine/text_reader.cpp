// TextReader: logical lines, tokens and strict number parsing.
#include "engine/text_reader.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace hemirad {

std::string quote(std::string_view token) {
    std::string out = "'";
    const std::size_t limit = 40;
    for (std::size_t i = 0; i < token.size() && i < limit; ++i) {
        const auto c = static_cast<unsigned char>(token[i]);
        if (c >= 32 && c < 127) {
            out += static_cast<char>(c);
        } else {
            static const char* hex = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (token.size() > limit) out += "...";
    return out + "'";
}

bool TextReader::next() {
    if (m_pos >= m_text.size()) return false;
    m_line = m_nextLine;
    m_joined.clear();
    bool joined = false;
    for (;;) {
        std::size_t end = m_text.find('\n', m_pos);
        if (end == std::string_view::npos) end = m_text.size();
        std::string_view piece = m_text.substr(m_pos, end - m_pos);
        m_pos = end + 1;
        ++m_nextLine;
        if (!piece.empty() && piece.back() == '\r') piece.remove_suffix(1);
        if (!piece.empty() && piece.back() == '\\' && m_pos < m_text.size()) {
            m_joined.append(piece.substr(0, piece.size() - 1)).push_back(' ');
            joined = true;
            continue;
        }
        if (joined) {
            m_joined.append(piece);
            m_current = m_joined;
        } else {
            m_current = piece;
        }
        break;
    }
    m_tokens.clear();
    std::size_t i = 0;
    const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r'; };
    while (i < m_current.size()) {
        while (i < m_current.size() && space(m_current[i])) ++i;
        const std::size_t start = i;
        while (i < m_current.size() && !space(m_current[i])) ++i;
        if (i > start) m_tokens.push_back(m_current.substr(start, i - start));
    }
    return true;
}

double TextReader::number(std::size_t k, const char* what) const {
    if (k >= m_tokens.size()) fail(std::string("missing ") + what);
    const std::string token(m_tokens[k]);
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') fail(std::string(what) + " " + quote(token) + " is not a number");
    if (!std::isfinite(value))
        fail(std::string(what) + " " + quote(token) + " is not a finite number");
    return value;
}

long TextReader::integer(std::size_t k, const char* what) const {
    if (k >= m_tokens.size()) fail(std::string("missing ") + what);
    const std::string token(m_tokens[k]);
    errno = 0;
    char* end = nullptr;
    const long value = std::strtol(token.c_str(), &end, 10);
    if (end == token.c_str() || *end != '\0') fail(std::string(what) + " " + quote(token) + " is not an integer");
    if (errno == ERANGE) fail(std::string(what) + " " + quote(token) + " is out of range");
    return value;
}

std::string TextReader::rest(std::size_t k) const {
    std::string out;
    for (std::size_t i = k; i < m_tokens.size(); ++i) {
        if (i > k) out += ' ';
        out += m_tokens[i];
    }
    return out;
}

}  // namespace hemirad
