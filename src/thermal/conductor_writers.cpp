// Writers of the thermal tables and the conductor formats.
#include "thermal/conductor_writers.hpp"

#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "engine/error.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <limits>

namespace hemirad::thermal {
namespace {


/// Names in the conductor formats' comments: one line, no control characters.
std::string commentName(const std::string& name) {
    std::string out;
    for (const char c : name) out += (static_cast<unsigned char>(c) < 0x20) ? ' ' : c;
    return out;
}

void precise(std::ostream& out) { out << std::setprecision(std::numeric_limits<double>::max_digits10); }

/// Lines of a conductor list, built in memory and written a megabyte at a time: 10^7 couplings in
/// seconds, not the minute that formatted stream insertion takes. Numbers in their shortest text
/// that reads back to the same double (std::to_chars).
class LineBuffer {
public:
    explicit LineBuffer(std::ostream& out) : m_out(out) { m_text.reserve(kFlush + 256); }
    ~LineBuffer() { flush(); }
    LineBuffer& operator<<(const std::string& text) { m_text += text; return *this; }
    LineBuffer& operator<<(const char* text) { m_text += text; return *this; }
    LineBuffer& operator<<(char c) { m_text += c; return *this; }
    LineBuffer& operator<<(double v) { return number(v); }
    LineBuffer& operator<<(std::uint64_t v) { return number(v); }
    LineBuffer& operator<<(std::uint32_t v) { return number(v); }
    /// Ends a line; writes out what has gathered past the flush size.
    void endLine() {
        m_text += '\n';
        if (m_text.size() >= kFlush) flush();
    }
    void flush() {
        m_out.write(m_text.data(), std::streamsize(m_text.size()));
        m_text.clear();
    }

private:
    static constexpr std::size_t kFlush = std::size_t(1) << 20;
    template <typename T>
    LineBuffer& number(T v) {
        char digits[32];
        const auto end = std::to_chars(digits, digits + sizeof digits, v).ptr;
        m_text.append(digits, end);
        return *this;
    }
    std::ostream& m_out;
    std::string m_text;
};

}  // namespace

void writePatchTable(const std::string& path, const Scene& scene, const ThermalModel& model, const ThermalSolution& s) {
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    precise(out);
    out << "patch,object,area (m^2),emissivity,specular,condition,T (K),T (C),J (W/m^2),H (W/m^2),absorbed solar (W/m^2),"
           "q (W/m^2),Q (W)\n";
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        out << i << ',' << csvField(scene.objects[p.object]) << ',' << s.areaM2[i] << ',' << model.surface[i].emissivity << ','
            << model.surface[i].specular << ','
            << (model.condition[i].kind == Condition::Kind::Temperature  ? "temperature"
                : model.condition[i].kind == Condition::Kind::Flux       ? "flux"
                                                                         : "isothermal")
            << ',';
        if (std::isfinite(s.T[i])) out << s.T[i] << ',' << s.T[i] - kCelsiusZero;
        else out << ',';
        out << ',' << s.J[i] << ',' << s.H[i] << ',' << (model.absorbedExternal.empty() ? 0.0 : model.absorbedExternal[i])
            << ',' << s.q[i] << ',' << s.Q[i] << '\n';
    }
    file.commit();
}

void writeObjectThermalTable(const std::string& path, const Scene& scene, const ThermalSolution& s) {
    struct Sum {
        std::size_t patches = 0;
        double area = 0, tArea = 0, tCovered = 0, tMin = INFINITY, tMax = -INFINITY, Q = 0;
    };
    std::vector<Sum> sums(scene.objects.size());
    for (PatchId i = 0; i < scene.size(); ++i) {
        Sum& o = sums[scene.patches[i].object];
        ++o.patches;
        o.area += s.areaM2[i];
        o.Q += s.Q[i];
        if (std::isfinite(s.T[i])) {
            o.tArea += s.T[i] * s.areaM2[i];
            o.tCovered += s.areaM2[i];
            o.tMin = std::min(o.tMin, s.T[i]);
            o.tMax = std::max(o.tMax, s.T[i]);
        }
    }
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    precise(out);
    out << "object,patches,area (m^2),T_mean (K),T_min (K),T_max (K),q_mean (W/m^2),Q (W)\n";
    for (std::size_t o = 0; o < sums.size(); ++o) {
        const Sum& x = sums[o];
        if (!x.patches) continue;
        out << csvField(scene.objects[o]) << ',' << x.patches << ',' << x.area << ',';
        if (x.tCovered > 0) out << x.tArea / x.tCovered << ',' << x.tMin << ',' << x.tMax;
        else out << ",,";
        out << ',' << x.Q / x.area << ',' << x.Q << '\n';
    }
    out << "environment,,,,,,," << s.environmentPower << '\n';
    file.commit();
}

void writeExchangeMatrix(const std::string& path, const std::vector<std::string>& nodes,
                         const std::vector<std::vector<double>>& Q) {
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    precise(out);
    out << "Q from \\ to (W)";
    for (const std::string& n : nodes) out << ',' << csvField(n);
    out << ",environment,total\n";
    for (std::size_t I = 0; I < nodes.size(); ++I) {
        out << csvField(nodes[I]);
        double total = 0.0;
        for (const double q : Q[I]) {
            out << ',' << q;
            total += q;
        }
        out << ',' << total << '\n';
    }
    file.commit();
}

const std::vector<std::string>& conductorFormats() {
    static const std::vector<std::string> formats = {"csv", "mtx", "esatan", "sinda"};
    return formats;
}

std::string conductorFormatFor(const std::string& path) {
    const auto dot = path.rfind('.');
    if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return "";
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == "csv" || ext == "mtx") return ext;
    if (ext == "esatan" || ext == "cnd") return "esatan";
    if (ext == "sinda" || ext == "inp") return "sinda";
    return "";
}

void writeConductors(const std::string& path, const std::string& format, const Conductors& c, std::uint32_t environmentNode) {
    const std::size_t K = c.nodes.size();
    if (environmentNode <= K && format != "csv" && format != "mtx")
        throw Error("thermal: the environment node number " + std::to_string(environmentNode) + " collides with the " +
                    std::to_string(K) + " surface nodes");
    auto number = [&](std::uint32_t node) { return node < K ? node + 1 : environmentNode; };
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    precise(out);
    LineBuffer lines(out);
    if (format == "csv") {
        std::vector<std::string> fields(K + 1, "environment");
        for (std::size_t I = 0; I < K; ++I) fields[I] = csvField(c.nodes[I]);
        out << "node_a,node_b,GR (m^2)\n";
        for (const Coupling& k : c.couplings) {
            lines << fields[k.a] << ',' << fields[std::min<std::size_t>(k.b, K)] << ',' << k.gr;
            lines.endLine();
        }
    } else if (format == "mtx") {
        out << "%%MatrixMarket matrix coordinate real symmetric\n"
               "% hemirad radiative conductors GR_ab (m^2), upper triangle given as lower: row > column\n";
        for (std::size_t I = 0; I < K; ++I) out << "% node " << I + 1 << " " << commentName(c.nodes[I]) << "\n";
        out << "% node " << K + 1 << " environment\n";
        out << K + 1 << ' ' << K + 1 << ' ' << c.couplings.size() << '\n';
        for (const Coupling& k : c.couplings) {
            lines << k.b + 1 << ' ' << k.a + 1 << ' ' << k.gr;
            lines.endLine();
        }
    } else if (format == "esatan") {
        out << "# Radiative conductors from hemirad (GR = eps_i A_i B_ij, m^2; Q = sigma GR (T_a^4 - T_b^4)).\n"
               "# Paste into the $CONDUCTORS block of an ESATAN-TMS model; node numbers:\n";
        for (std::size_t I = 0; I < K; ++I) out << "#   " << I + 1 << " = " << commentName(c.nodes[I]) << "\n";
        out << "#   " << environmentNode << " = environment (a boundary node at the environment temperature)\n";
        for (const Coupling& k : c.couplings) {
            lines << "GR(" << number(k.a) << ", " << number(k.b) << ") = " << k.gr << ';';
            lines.endLine();
        }
    } else if (format == "sinda") {
        out << "C Radiation conductors from hemirad: GR = eps_i A_i B_ij in m^2 (SI); set SIGMA = 5.670374419E-8\n"
               "C and ABSZRO = 0.0 (temperatures in K) or -273.15 (deg C) in CONTROL DATA. Node numbers:\n";
        for (std::size_t I = 0; I < K; ++I) out << "C   " << I + 1 << " = " << commentName(c.nodes[I]) << "\n";
        out << "C   " << environmentNode << " = environment (a boundary node)\n";
        out << "HEADER CONDUCTOR DATA, MAIN\n";
        std::uint64_t id = 1;
        for (const Coupling& k : c.couplings) {
            lines << '-' << id++ << ", " << number(k.a) << ", " << number(k.b) << ", " << k.gr;
            lines.endLine();
        }
    } else {
        throw Error("thermal: unknown conductor format '" + format + "' (csv, mtx, esatan, sinda)");
    }
    lines.flush();
    file.commit();
}

}  // namespace hemirad::thermal
