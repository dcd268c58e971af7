// Counted, visible-by-default warnings: the first few of each kind are printed, all are summarised.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>

namespace hemirad {

class Warnings {
public:
    using Sink = std::function<void(const std::string&)>;

    /// Prints through `sink` (default: "hemirad: warning: ..." on stderr); null sink = silent.
    explicit Warnings(Sink sink = stderrSink(), std::size_t printedPerKind = 5);

    /// Records one warning of `kind` (a short plural noun phrase, e.g. "degenerate patches skipped").
    void add(const std::string& kind, const std::string& message);
    /// Records `n` warnings of `kind` summarised by one printed message.
    void add(const std::string& kind, const std::string& message, std::size_t n);

    std::size_t count() const { return m_total; }
    std::size_t count(const std::string& kind) const;
    /// The first message recorded for `kind` ("" when none): where a count needs its example.
    std::string firstMessage(const std::string& kind) const;
    /// "3 warnings: 2 non-planar patches, 1 materials with rho + s > 1" or "" when there were none.
    std::string summary() const;

    static Sink stderrSink();

private:
    Sink m_sink;
    std::size_t m_printedPerKind;
    std::size_t m_total = 0;
    std::map<std::string, std::size_t> m_counts;
    std::map<std::string, std::string> m_first;
};

}  // namespace hemirad
