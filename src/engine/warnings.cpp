// Counted warnings with a bounded number printed per kind.
#include "engine/warnings.hpp"

#include "engine/console.hpp"

#include <iostream>

namespace hemirad {

Warnings::Warnings(Sink sink, std::size_t printedPerKind)
    : m_sink(std::move(sink)), m_printedPerKind(printedPerKind) {}

Warnings::Sink Warnings::stderrSink() {
    return [](const std::string& message) { writeWhole(std::cerr, "hemirad: warning: " + message + '\n'); };
}

void Warnings::add(const std::string& kind, const std::string& message) {
    std::size_t& n = ++m_counts[kind];
    ++m_total;
    m_first.emplace(kind, message);
    if (!m_sink) return;
    if (n <= m_printedPerKind) m_sink(message);
    if (n == m_printedPerKind + 1) m_sink("(further " + kind + " are counted, not printed)");
}

void Warnings::add(const std::string& kind, const std::string& message, std::size_t n) {
    if (n == 0) return;
    m_counts[kind] += n;
    m_total += n;
    m_first.emplace(kind, message);
    if (m_sink) m_sink(message);
}

std::size_t Warnings::count(const std::string& kind) const {
    auto it = m_counts.find(kind);
    return it == m_counts.end() ? 0 : it->second;
}

std::string Warnings::firstMessage(const std::string& kind) const {
    auto it = m_first.find(kind);
    return it == m_first.end() ? std::string() : it->second;
}

std::string Warnings::summary() const {
    if (m_total == 0) return {};
    std::string text = std::to_string(m_total) + (m_total == 1 ? " warning: " : " warnings: ");
    bool first = true;
    for (const auto& [kind, n] : m_counts) {
        if (!first) text += ", ";
        text += std::to_string(n) + " " + kind;
        first = false;
    }
    return text;
}

}  // namespace hemirad
