// Test support: closed-form view factors (Howell's catalogue), scene builders, temporary files.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/obj_loader.hpp"
#include "engine/scene.hpp"
#include "engine/warnings.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <sys/wait.h>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <unistd.h>

namespace hemirad::test {

/// Howell C-11: identical parallel directly opposed rectangles a x b at distance c.
inline double c11(double a, double b, double c) {
    const double X = a / c, Y = b / c;
    const double x2 = X * X, y2 = Y * Y;
    return 2.0 / (kPi * X * Y) *
           (std::log(std::sqrt((1 + x2) * (1 + y2) / (1 + x2 + y2))) +
            X * std::sqrt(1 + y2) * std::atan(X / std::sqrt(1 + y2)) +
            Y * std::sqrt(1 + x2) * std::atan(Y / std::sqrt(1 + x2)) - X * std::atan(X) - Y * std::atan(Y));
}

/// Howell C-12 (parallel rectangles in general position, by superposition of corner terms): from
/// [x1, x2] x [y1, y2] on one plane to [u1, u2] x [v1, v2] on a parallel plane at distance z.
inline double parallelRectangles(double x1, double x2, double y1, double y2, double u1, double u2, double v1,
                                 double v2, double z) {
    auto g = [z](double x, double y) {
        const double a = std::sqrt(x * x + z * z), b = std::sqrt(y * y + z * z);
        return y * a * std::atan(y / a) + x * b * std::atan(x / b) - 0.5 * z * z * std::log(x * x + y * y + z * z);
    };
    const double xs[2] = {x1, x2}, ys[2] = {y1, y2}, us[2] = {u1, u2}, vs[2] = {v1, v2};
    double sum = 0.0;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
            for (int k = 0; k < 2; ++k)
                for (int l = 0; l < 2; ++l)
                    sum += ((i + j + k + l) % 2 ? -1.0 : 1.0) * g(xs[i] - us[k], ys[j] - vs[l]);
    return sum / (2.0 * kPi * (x2 - x1) * (y2 - y1));
}

/// Howell C-14: perpendicular rectangles with a common edge l; emitter w x l, receiver h x l.
inline double c14(double w, double h, double l) {
    const double W = w / l, H = h / l;
    const double W2 = W * W, H2 = H * H, S = W2 + H2;
    const double a = (1 + W2) * (1 + H2) / (1 + S);
    const double b = std::pow(W2 * (1 + S) / ((1 + W2) * S), W2);
    const double c = std::pow(H2 * (1 + S) / ((1 + H2) * S), H2);
    return 1.0 / (kPi * W) *
           (W * std::atan(1 / W) + H * std::atan(1 / H) - std::sqrt(S) * std::atan(1 / std::sqrt(S)) +
            0.25 * std::log(a * b * c));
}

/// Howell C-41: coaxial parallel disks r1 -> r2 at distance h.
inline double c41(double r1, double r2, double h) {
    const double R1 = r1 / h, R2 = r2 / h;
    const double X = 1 + (1 + R2 * R2) / (R1 * R1);
    return 0.5 * (X - std::sqrt(X * X - 4 * (R2 / R1) * (R2 / R1)));
}

/// Howell B-3: differential element parallel to an a x b rectangle at distance c, its normal
/// through a corner of the rectangle.
inline double b3(double a, double b, double c) {
    const double A = a / c, B = b / c;
    return (A / std::sqrt(1 + A * A) * std::atan(B / std::sqrt(1 + A * A)) +
            B / std::sqrt(1 + B * B) * std::atan(A / std::sqrt(1 + B * B))) /
           (2 * kPi);
}

/// From (px, py, 0) facing +z to the rectangle [x0, x1] x [y0, y1] at height c (B-3 per corner).
inline double toRectangle(double px, double py, double x0, double x1, double y0, double y1, double c) {
    auto corner = [&](double a, double b) {
        return (a < 0 ? -1.0 : 1.0) * (b < 0 ? -1.0 : 1.0) * b3(std::abs(a), std::abs(b), c);
    };
    return corner(x1 - px, y1 - py) - corner(x0 - px, y1 - py) - corner(x1 - px, y0 - py) + corner(x0 - px, y0 - py);
}

/// doctest's Approx within `eps` relative: its default scale of 1 makes the tolerance absolute
/// for values below 1, as form factors are (Approx(0.02).epsilon(1e-5) passes 0.0201).
inline doctest::Approx relative(double expected, double eps) {
    return doctest::Approx(expected).epsilon(eps).scale(1e-300);  // not 0: 0 == relative(0, eps) holds
}

constexpr double kCubeOpposite = 0.1998248957;
constexpr double kCubeAdjacent = 0.2000437761;

/// Builds scenes polygon by polygon: each polygon gets its own vertices.
class SceneBuilder {
public:
    SceneBuilder() {
        Material m;
        m.name = "default";
        m.rho = Rgb::Constant(0.5);
        scene.materials.push_back(m);
        scene.objects.push_back("default");
    }
    /// Adds a material; returns its index.
    std::uint32_t material(const std::string& name, Rgb rho, Rgb emission = Rgb::Zero(), double specular = 0.0) {
        Material m;
        m.name = name;
        m.rho = rho;
        m.emission = emission;
        m.specular = specular;
        m.ks = Rgb::Constant(specular);
        m.illum = specular > 0 ? 3 : 1;
        scene.materials.push_back(m);
        return static_cast<std::uint32_t>(scene.materials.size() - 1);
    }
    PatchId polygon(const std::vector<Vec3>& points, std::uint32_t materialId = 0) {
        std::vector<std::uint32_t> ids;
        for (const Vec3& p : points) {
            ids.push_back(static_cast<std::uint32_t>(scene.vertices.size()));
            scene.vertices.push_back(p);
        }
        return scene.addPatch(ids, materialId, 0);
    }
    /// Axis-aligned rectangle in the plane `axis` = `offset`; normal along +axis or -axis.
    PatchId rectangle(int axis, double offset, double u0, double u1, double v0, double v1, bool positive,
                      std::uint32_t materialId = 0) {
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        auto point = [&](double u, double v) {
            Vec3 p;
            p[axis] = offset;
            p[a] = u;
            p[b] = v;
            return p;
        };
        std::vector<Vec3> pts = {point(u0, v0), point(u1, v0), point(u1, v1), point(u0, v1)};
        if (!positive) std::swap(pts[1], pts[3]);
        return polygon(pts, materialId);
    }
    /// Regular n-gon approximating a disk of radius r centred at c in the plane z = c.z, normal +-z.
    PatchId disk(const Vec3& c, double r, int n, bool up, std::uint32_t materialId = 0) {
        std::vector<Vec3> pts;
        for (int k = 0; k < n; ++k) {
            const double phi = 2 * kPi * (up ? k : -k) / n;
            pts.push_back(c + Vec3(r * std::cos(phi), r * std::sin(phi), 0));
        }
        return polygon(pts, materialId);
    }
    Scene scene;
};

/// Mean over rows of sum_j |A_ij - B_ij|.
inline double meanRowL1(const FormFactors& A, const FormFactors& B) {
    double total = 0.0;
    for (std::size_t i = 0; i < A.size(); ++i) {
        double row = 0.0;
        for (std::uint64_t k = A.rowBegin(i); k < A.rowEnd(i); ++k)
            row += std::abs(A.values()[k] - B.at(i, A.columns()[k]));
        for (std::uint64_t k = B.rowBegin(i); k < B.rowEnd(i); ++k)
            if (A.at(i, B.columns()[k]) == 0.0) row += B.values()[k];
        total += row;
    }
    return total / double(A.size());
}

/// The closed unit cube [0,1]^3 of six inward-facing quads; floor (y = 0) first.
inline Scene unitCube() {
    SceneBuilder b;
    b.rectangle(1, 0, 0, 1, 0, 1, true);   // floor y=0, normal +y
    b.rectangle(1, 1, 0, 1, 0, 1, false);  // ceiling
    b.rectangle(0, 0, 0, 1, 0, 1, true);   // x=0
    b.rectangle(0, 1, 0, 1, 0, 1, false);  // x=1
    b.rectangle(2, 0, 0, 1, 0, 1, true);   // z=0
    b.rectangle(2, 1, 0, 1, 0, 1, false);  // z=1
    return b.scene;
}

inline std::string sourcePath(const std::string& relative) { return std::string(HEMIRAD_SOURCE_DIR) + "/" + relative; }

/// Lambert's factor from the point x (unit normal n) to the polygon p wholly above x's plane, in the
/// arc-cosine form (independent of the library's point_polygon.cpp).
inline double lambertFactor(const Vec3& x, const Vec3& n, const std::vector<Vec3>& p) {
    double sum = 0.0;
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec3 a = (p[k] - x).normalized(), b = (p[(k + 1) % p.size()] - x).normalized();
        const Vec3 c = a.cross(b);
        if (c.norm() < 1e-300) continue;
        sum += std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * n.dot(c) / c.norm();
    }
    return std::abs(sum) / (2.0 * kPi);
}

/// A scene bundled in scenes/, loaded with its warnings kept quiet.
inline Scene bundledScene(const std::string& name) {
    Warnings w(nullptr);
    return loadObj(sourcePath("scenes/" + name), w);
}

/// A fresh directory under the build tree for one test's files.
inline std::filesystem::path tempDir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("hemirad-test-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::string writeFile(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
}

/// A whole file's bytes ("" if it cannot be read).
inline std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

/// What a shell command printed (stdout, and stderr where the command redirects it) and its exit status.
struct CommandResult {
    int status;
    std::string output;
};

/// Runs a shell command to its end, capturing its output.
inline CommandResult runCommand(const std::string& command) {
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) throw std::runtime_error("popen failed: " + command);
    std::string output;
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
    const int status = ::pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

/// "env LD_PRELOAD=PROBE HEMIRAD_WRITE_LOG=LOG " in front of a command, or of one rank's program in
/// an mpirun application context: the probe (tests/write_log.cpp) appends each write(2)/writev(2)
/// call the program (and its children) make on descriptor 1 or 2 to LOG, whole; loggedWrites reads
/// it back. No ptrace, which CI may forbid. Text printed through stdio (std::cerr,
/// fprintf) is not seen, so a check for it fails rather than passes. The ASAN_OPTIONS let the
/// sanitizer build's runtime accept a library preloaded ahead of it.
inline std::string logWrites(const std::string& log) {
    return "env ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0 LD_PRELOAD='" +
           std::string(HEMIRAD_TEST_WRITE_LOG) + "' HEMIRAD_WRITE_LOG='" + log + "' ";
}

/// One write(2) or writev(2) call on standard output (fd 1) or standard error (fd 2): its bytes.
struct LoggedWrite {
    int fd;
    std::string text;
};

/// The calls in a log of logWrites, in the order they were made ([] if there is no log). Each record
/// is "FD LENGTH\n", LENGTH bytes, "\n"; a malformed one throws.
inline std::vector<LoggedWrite> loggedWrites(const std::filesystem::path& log) {
    const std::string text = readText(log);
    std::vector<LoggedWrite> writes;
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t newline = text.find('\n', at);
        int fd = -1;
        std::size_t length = 0;
        int used = 0;
        if (newline == std::string::npos ||
            std::sscanf(text.substr(at, newline - at).c_str(), "%d %zu%n", &fd, &length, &used) != 2 ||
            std::size_t(used) != newline - at || length >= text.size() - newline - 1 ||
            text[newline + 1 + length] != '\n')
            throw std::runtime_error("malformed write log " + log.string() + " at byte " + std::to_string(at));
        writes.push_back({fd, text.substr(newline + 1, length)});
        at = newline + 1 + length + 1;
    }
    return writes;
}

/// Whether one call in `writes` wrote exactly `text` to descriptor `fd`: all of it, and nothing else.
inline bool wroteWhole(const std::vector<LoggedWrite>& writes, int fd, const std::string& text) {
    for (const LoggedWrite& w : writes)
        if (w.fd == fd && w.text == text) return true;
    return false;
}

/// A log of logWrites as the checks print it on failure: one line per call, "fd N: TEXT".
inline std::string describeWrites(const std::vector<LoggedWrite>& writes) {
    std::string out;
    for (const LoggedWrite& w : writes) {
        out += "fd " + std::to_string(w.fd) + ": ";
        for (const char c : w.text) out += c == '\n' ? std::string("\\n") : std::string(1, c);
        out += '\n';
    }
    return out;
}

/// Warnings that are collected silently for assertions.
inline Warnings quietWarnings() { return Warnings(nullptr); }

}  // namespace hemirad::test
