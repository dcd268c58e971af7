// `hemirad check` end to end: the text report, the JSON document (parsed), exit statuses 0, 1 and 2.
#include "support.hpp"

#include <doctest/doctest.h>

#include <cctype>
#include <map>

using namespace hemirad;
using namespace hemirad::test;

namespace {

CommandResult runHemirad(const std::string& arguments) {
    return runCommand(std::string(HEMIRAD_BINARY) + " " + arguments + " 2>&1");
}

/// A strict little JSON reader: every scalar under its dotted path ("issues.slivers.count",
/// "issues.t_junctions.examples.0.patches.1"), strings unquoted; throws on malformed text.
class FlatJson {
public:
    explicit FlatJson(const std::string& text) : m_text(text) {
        value("");
        space();
        if (m_at != m_text.size()) fail("text after the document");
    }
    std::map<std::string, std::string> values;

private:
    [[noreturn]] void fail(const std::string& why) const {
        throw std::runtime_error("JSON at " + std::to_string(m_at) + ": " + why);
    }
    void space() {
        while (m_at < m_text.size() && std::isspace(static_cast<unsigned char>(m_text[m_at]))) ++m_at;
    }
    bool take(char c) {
        space();
        if (m_at < m_text.size() && m_text[m_at] == c) return ++m_at, true;
        return false;
    }
    std::string string() {
        if (!take('"')) fail("a string expected");
        std::string out;
        while (m_at < m_text.size() && m_text[m_at] != '"') {
            if (static_cast<unsigned char>(m_text[m_at]) < 0x20) fail("a raw control character");
            if (m_text[m_at] == '\\') ++m_at;
            out += m_text[m_at++];
        }
        if (!take('"')) fail("an unterminated string");
        return out;
    }
    static std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
    void value(const std::string& path) {
        space();
        if (take('{')) {
            if (take('}')) return;
            do {
                const std::string key = string();
                if (!take(':')) fail("':' expected");
                value(join(path, key));
            } while (take(','));
            if (!take('}')) fail("'}' expected");
        } else if (take('[')) {
            values[join(path, "size")] = "0";
            if (take(']')) return;
            std::size_t n = 0;
            do value(join(path, std::to_string(n++)));
            while (take(','));
            values[join(path, "size")] = std::to_string(n);
            if (!take(']')) fail("']' expected");
        } else if (m_at < m_text.size() && m_text[m_at] == '"') {
            values[path] = string();
        } else {
            const std::size_t start = m_at;
            while (m_at < m_text.size() && (std::isalnum(static_cast<unsigned char>(m_text[m_at])) ||
                                             std::string("+-.").find(m_text[m_at]) != std::string::npos))
                ++m_at;
            const std::string word = m_text.substr(start, m_at - start);
            if (word != "true" && word != "false" && word != "null") {
                std::size_t used = 0;
                try {
                    std::stod(word, &used);
                } catch (const std::exception&) {
                    fail("a value expected");
                }
                if (used != word.size()) fail("a malformed number '" + word + "'");
            }
            values[path] = word;
        }
    }
    const std::string& m_text;
    std::size_t m_at = 0;
};

// The unit cube whose ceiling is three triangles around a vertex inside the x = 1 wall's top edge
// (a T-junction, covered: closed), plus a sliver floating inside.
const char* kScene = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
v 1 1 0.5
f 2 1 5 6
f 5 1 4 8
f 2 6 7 3
f 2 3 4 1
f 6 5 8 7
f 4 3 9
f 4 9 7
f 4 7 8
)";

}  // namespace

TEST_CASE("hemirad check reports each issue's count, its examples with source lines, and the verdict") {
    const auto dir = tempDir("check-text");
    const std::string obj = writeFile(dir / "tcube.obj", kScene);
    const CommandResult r = runHemirad("check " + obj);
    CAPTURE(r.output);
    CHECK(r.status == 0);
    CHECK(r.output.find("8 patches, 9 vertices after welding") != std::string::npos);
    CHECK(r.output.find("T-junctions (a vertex inside another patch's edge, not a corner of it): 1 vertex-edge contacts") !=
          std::string::npos);
    CHECK(r.output.find("  patch 2 (line 12), patch 5 (line 15) at (1, 1, 0.5)") != std::string::npos);
    CHECK(r.output.find("effect on F: partial-edge contacts") != std::string::npos);
    CHECK(r.output.find("slivers (longest edge / minimum width above the limit): 0 patches") != std::string::npos);
    CHECK(r.output.find("open edges: 3 used by one patch, 3 of them covered by T-junction chains, 0 open") !=
          std::string::npos);
    CHECK(r.output.find("closed: yes (watertight and facing inward") != std::string::npos);
    std::filesystem::remove_all(dir);
}

TEST_CASE("hemirad check --json writes a document with the schema's keys, and --sliver-ratio sets the limit") {
    const auto dir = tempDir("check-json");
    std::string text = kScene;
    text += "v 0.2 0.5 0.5\nv 0.8 0.5 0.5\nv 0.5 0.51 0.5\nf 10 11 12\n";  // a sliver, line 21 (aspect 60)
    const std::string obj = writeFile(dir / "sliver.obj", text);
    CommandResult r = runHemirad("check " + obj + " --json " + (dir / "report.json").string());
    CAPTURE(r.output);
    REQUIRE(r.status == 0);
    FlatJson doc(readText(dir / "report.json"));
    auto& v = doc.values;
    CHECK(v["schema_version"] == "1");
    CHECK(v["scene"] == obj);
    CHECK(v["patches"] == "9");
    CHECK(v["sliver_ratio"] == "20");
    CHECK(v["relative_tolerance"] == "1e-06");
    CHECK(v["closed"] == "false");
    CHECK(v["watertight"] == "false");
    CHECK(v["meaningless"] == "false");
    CHECK(v["open_edges_raw"] == "6");
    CHECK(v["open_edges_covered"] == "3");
    for (const char* key : {"t_junctions", "duplicates", "overlapping_coplanar", "back_to_back", "inconsistent_orientation",
                            "non_manifold_edges", "open_edges", "slivers", "zero_area", "non_planar"}) {
        CAPTURE(key);
        const std::string issue = std::string("issues.") + key;
        CHECK(v.count(issue + ".count"));
        CHECK(!v[issue + ".effect"].empty());
        CHECK(v.count(issue + ".examples.size"));
    }
    CHECK(v["issues.t_junctions.count"] == "1");
    CHECK(v["issues.t_junctions.examples.0.patches.0"] == "2");
    CHECK(v["issues.t_junctions.examples.0.lines.1"] == "15");
    CHECK(v["issues.t_junctions.examples.0.points.0.2"] == "0.5");
    CHECK(v["issues.slivers.count"] == "1");
    CHECK(v["issues.slivers.examples.0.patches.0"] == "8");
    CHECK(v["issues.slivers.examples.0.lines.0"] == "21");
    CHECK(std::stod(v["issues.slivers.examples.0.value"]) == doctest::Approx(60.0));
    CHECK(v["issues.open_edges.count"] == "3");
    CHECK(v["issues.zero_area.skipped_by_loader"] == "0");

    // A higher limit: no sliver; the document on standard output, the text report on standard error.
    r = runCommand(std::string(HEMIRAD_BINARY) + " check " + obj + " --sliver-ratio 100 --json - 2>/dev/null");
    REQUIRE(r.status == 0);
    FlatJson piped(r.output);
    CHECK(piped.values["issues.slivers.count"] == "0");
    CHECK(piped.values["sliver_ratio"] == "100");
    std::filesystem::remove_all(dir);
}

TEST_CASE("hemirad check exits 1 only where F would be meaningless, 2 on usage errors") {
    const auto dir = tempDir("check-status");
    // Warnings only (open edges, a face the loader skipped): 0.
    std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n";
    CommandResult r = runHemirad("check " + writeFile(dir / "open.obj", text));
    CAPTURE(r.output);
    CHECK(r.status == 0);
    CHECK(r.output.find("zero-area patches (narrower than the tolerance): 1 patches") != std::string::npos);
    CHECK(r.output.find("1 skipped by the loader (no patch index): ") != std::string::npos);
    CHECK(r.output.find("closed: no (3 open edges") != std::string::npos);

    // Every patch narrower than the tolerance: the report, then 1.
    r = runHemirad("check " + writeFile(dir / "thin.obj", "v 0 0 0\nv 1 0 0\nv 0.5 1e-9 0\nf 1 2 3\n"));
    CHECK(r.status == 1);
    CHECK(r.output.find("F would be meaningless: every patch has zero area") != std::string::npos);
    // The loader's errors (non-finite coordinates, nothing to compute) are runtime errors: 1.
    r = runHemirad("check " + writeFile(dir / "nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"));
    CHECK(r.status == 1);
    CHECK(r.output.find("nan.obj:2:") != std::string::npos);
    r = runHemirad("check " + (dir / "missing.obj").string());
    CHECK(r.status == 1);

    r = runHemirad("check");
    CHECK(r.status == 2);
    CHECK(r.output.find("'check' takes exactly one input file, got 0") != std::string::npos);
    r = runHemirad("check " + (dir / "open.obj").string() + " --sliver-ratio 0.5");
    CHECK(r.status == 2);
    CHECK(r.output.find("--sliver-ratio 0.5 is out of range") != std::string::npos);
    r = runHemirad("check " + (dir / "open.obj").string() + " -o x.obj");
    CHECK(r.status == 2);
    CHECK(r.output.find("option '-o' does not apply to 'check'") != std::string::npos);
    r = runHemirad("check " + (dir / "open.obj").string() + " --samples 96");
    CHECK(r.status == 2);
    r = runHemirad("info F.hff --sliver-ratio 10");
    CHECK(r.status == 2);
    CHECK(runHemirad("help").output.find("check SCENE ") != std::string::npos);
    std::filesystem::remove_all(dir);
}
