// `hemirad check SCENE.obj [--json FILE]`: what the mesh will do to F, issue by issue (README, "Mesh check").
#include "cli/commands.hpp"
#include "cli/report.hpp"
#include "engine/atomic_file.hpp"
#include "engine/mesh_check.hpp"
#include "engine/scene_loader.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace hemirad {
namespace {

/// The JSON document's layout version (README, "Mesh check: JSON"); raise it when a key changes meaning.
constexpr int kSchemaVersion = 1;

std::string number(double v) {
    if (!std::isfinite(v)) return "null";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.10g", v);
    return buffer;
}

std::string quoted(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
            out += buffer;
        } else {
            out += c;
        }
    }
    return out + '"';
}

std::string point(const Vec3& x) { return "[" + number(x.x()) + ", " + number(x.y()) + ", " + number(x.z()) + "]"; }

std::string json(const MeshReport& r, const std::string& scene) {
    std::ostringstream out;
    out << "{\n  \"schema_version\": " << kSchemaVersion << ",\n  \"scene\": " << quoted(scene)
        << ",\n  \"patches\": " << r.patches << ",\n  \"vertices\": " << r.vertices << ",\n  \"edges\": " << r.edges
        << ",\n  \"extent\": " << number(r.extent) << ",\n  \"tolerance\": " << number(r.tolerance)
        << ",\n  \"relative_tolerance\": " << number(r.options.relativeTolerance)
        << ",\n  \"sliver_ratio\": " << number(r.options.sliverRatio) << ",\n  \"planarity\": " << number(r.options.planarity)
        << ",\n  \"closed\": " << (r.closed ? "true" : "false") << ",\n  \"closed_reason\": " << quoted(r.closedReason)
        << ",\n  \"watertight\": " << (r.watertight ? "true" : "false")
        << ",\n  \"signed_volume\": " << number(r.signedVolume) << ",\n  \"open_edges_raw\": " << r.openEdgesRaw
        << ",\n  \"open_edges_covered\": " << r.openEdgesCovered
        << ",\n  \"meaningless\": " << (r.meaningless ? "true" : "false")
        << ",\n  \"meaningless_reason\": " << quoted(r.meaninglessReason) << ",\n  \"issues\": {";
    for (std::size_t k = 0; k < r.issues.size(); ++k) {
        const MeshIssue& issue = r.issues[k];
        out << (k ? "," : "") << "\n    " << quoted(issue.key) << ": {\n      \"title\": " << quoted(issue.title)
            << ",\n      \"unit\": " << quoted(issue.unit) << ",\n      \"count\": " << issue.count
            << ",\n      \"value_name\": " << quoted(issue.valueName) << ",\n      \"effect\": " << quoted(issue.effect);
        if (issue.key == "duplicates") out << ",\n      \"reversed\": " << r.duplicatesReversed;
        if (issue.key == "zero_area")
            out << ",\n      \"skipped_by_loader\": " << r.zeroAreaSkipped
                << ",\n      \"skipped_note\": " << quoted(r.zeroAreaSkippedNote);
        out << ",\n      \"examples\": [";
        for (std::size_t e = 0; e < issue.examples.size(); ++e) {
            const MeshExample& x = issue.examples[e];
            out << (e ? "," : "") << "\n        {\"patches\": [";
            for (std::size_t j = 0; j < x.patches.size(); ++j) out << (j ? ", " : "") << x.patches[j];
            out << "], \"lines\": [";
            for (std::size_t j = 0; j < x.lines.size(); ++j) out << (j ? ", " : "") << x.lines[j];
            out << "], \"points\": [";
            for (std::size_t j = 0; j < x.points.size(); ++j) out << (j ? ", " : "") << point(x.points[j]);
            out << "], \"value\": " << number(x.value) << "}";
        }
        out << (issue.examples.empty() ? "]" : "\n      ]") << "\n    }";
    }
    out << "\n  }\n}\n";
    return out.str();
}

std::string brief(double v) {
    std::ostringstream out;
    out.precision(6);
    out << v;
    return out.str();
}

std::string patchName(PatchId id, int line) {
    return "patch " + std::to_string(id) + (line > 0 ? " (line " + std::to_string(line) + ")" : " (no source line)");
}

void text(const Reporter& reporter, const MeshReport& r, const std::string& scene) {
    reporter.line(scene + ": " + std::to_string(r.patches) + " patches, " + std::to_string(r.vertices) +
                  " vertices after welding, " + std::to_string(r.edges) + " edges");
    reporter.line("  tolerance " + brief(r.tolerance) + " (" + brief(r.options.relativeTolerance) + " x extent " +
                  brief(r.extent) + "); sliver: longest edge / minimum width > " + brief(r.options.sliverRatio) +
                  "; non-planar: a corner off the Newell plane by > " + brief(r.options.planarity) + " x longest edge");
    for (const MeshIssue& issue : r.issues) {
        reporter.line(issue.title + ": " + std::to_string(issue.count) + " " + issue.unit);
        if (issue.count == 0) continue;
        if (issue.key == "duplicates" && r.duplicatesReversed)
            reporter.line("  " + std::to_string(r.duplicatesReversed) + " of them reversed");
        if (issue.key == "zero_area" && r.zeroAreaSkipped)
            reporter.line("  " + std::to_string(r.zeroAreaSkipped) + " skipped by the loader (no patch index): " +
                          r.zeroAreaSkippedNote);
        for (const MeshExample& x : issue.examples) {
            std::string line = "  ";
            for (std::size_t j = 0; j < x.patches.size() && j < 4; ++j)
                line += (j ? ", " : "") + patchName(x.patches[j], x.lines[j]);
            if (x.patches.size() > 4) line += ", ...";
            for (std::size_t j = 0; j < x.points.size(); ++j)
                line += (j ? " - " : " at ") + std::string("(") + brief(x.points[j].x()) + ", " + brief(x.points[j].y()) +
                        ", " + brief(x.points[j].z()) + ")";
            if (!issue.valueName.empty()) line += "; " + issue.valueName + " " + brief(x.value);
            reporter.line(line);
        }
        if (issue.count > issue.examples.size())
            reporter.line("  ... and " + std::to_string(issue.count - issue.examples.size()) + " more");
        reporter.line("  effect on F: " + issue.effect);
    }
    reporter.line("open edges: " + std::to_string(r.openEdgesRaw) + " used by one patch, " +
                  std::to_string(r.openEdgesCovered) + " of them covered by T-junction chains, " +
                  std::to_string(r.issue(MeshIssueKind::OpenEdges).count) + " open");
    reporter.line(std::string("closed: ") + (r.closed ? "yes" : "no") + " (" + r.closedReason + ")");
    if (r.meaningless) reporter.line("F would be meaningless: " + r.meaninglessReason);
}

}  // namespace

int runCheck(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const std::string& path = options.inputs.at(0);
    timings.start("load scene");
    const Scene scene = loadScene(path, warnings, {options.materials});  // the one place the scene is read
    timings.start("check mesh");
    MeshCheckOptions settings;
    settings.relativeTolerance = options.relativeTolerance;
    settings.sliverRatio = options.sliverRatio;
    MeshReport report = checkMesh(scene, settings);
    addSkippedZeroArea(report, warnings.count("degenerate patches skipped"),
                       warnings.firstMessage("degenerate patches skipped"));
    timings.stop();
    text(reporter, report, path);
    if (!options.jsonPath.empty()) {
        AtomicFile file(options.jsonPath, false);
        file.stream() << json(report, path);
        file.commit();
    }
    finishCommand(reporter, timings, warnings);
    return report.meaningless ? 1 : 0;
}

}  // namespace hemirad
