// Reading and writing F: binary .hff (checked) and Matrix Market .mtx.
//
// .hff layout, little-endian, no padding:
//
//   offset      size       field
//   0           8          magic "HEMIRADF"
//   8           4          version (2; version 1 held float32 values, and is still read)
//   12          4          L = length of the parameter text
//   16          8          N, patches
//   24          8          nnz
//   32          8          scene hash (geometry + specular, Scene::geometryHash)
//   40          L          parameters, "key=value\n" lines (method, samples, origins, ...)
//   40+L        N          computed-row flags, 0 or 1 (rows of black patches may be skipped)
//   ...         8 (N+1)    row starts, uint64
//   ...         4 nnz      columns, uint32, strictly increasing within a row
//   ...         8 nnz      values, float64 (version 1: 4 nnz, float32)
//   end-8       8          checksum (word-wise FNV-1a) of every byte before it
#include "engine/form_factor_file.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"
#include "engine/form_factor_shards.hpp"
#include "engine/obj_loader.hpp"
#include "engine/text_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace hemirad {
namespace {

constexpr char kMagic[8] = {'H', 'E', 'M', 'I', 'R', 'A', 'D', 'F'};
constexpr std::uint32_t kVersion = 2;
/// Version 1 stored F's values as float32 (F was float then); it is read, widened to double.
constexpr std::uint32_t kFloatVersion = 1;
/// The bytes of one stored value in a file of `version`.
std::uint64_t valueBytes(std::uint32_t version) { return version == kFloatVersion ? 4 : 8; }
constexpr std::size_t kHeaderBytes = 40;
constexpr std::uint32_t kMaxParameterBytes = 1u << 20;
constexpr long kMaxPatches = 1L << 28;  // 268 M patches: far beyond memory for any F

/// FNV-1a over 64-bit words (bytes of a partial tail word are buffered), about 8x faster than bytewise.
class Checksum {
public:
    void add(const void* data, std::size_t size) {
        const auto* p = static_cast<const unsigned char*>(data);
        while (size > 0 && m_fill > 0) {
            push(*p++);
            --size;
        }
        for (; size >= 8; size -= 8, p += 8) {
            std::uint64_t word;
            std::memcpy(&word, p, 8);
            mix(word);
        }
        while (size-- > 0) push(*p++);
    }
    std::uint64_t value() const {
        std::uint64_t state = m_state;
        if (m_fill > 0) {
            std::uint64_t word = 0;
            std::memcpy(&word, m_tail, m_fill);
            state = (state ^ word ^ (std::uint64_t(m_fill) << 56)) * 0x100000001b3ULL;
        }
        return state ^ (state >> 29);
    }

private:
    void push(unsigned char c) {
        m_tail[m_fill & 7] = c;
        if (++m_fill == 8) {
            std::uint64_t word;
            std::memcpy(&word, m_tail, 8);
            m_fill = 0;
            mix(word);
        }
    }
    void mix(std::uint64_t word) { m_state = (m_state ^ word) * 0x100000001b3ULL; }

    std::uint64_t m_state = 0xcbf29ce484222325ULL;
    unsigned char m_tail[8] = {};
    std::size_t m_fill = 0;
};

std::string parameterText(const FormFactors& F) {
    std::string text;
    for (const auto& [key, value] : withProvenance(F.provenance, F.parameters)) text += key + "=" + value + "\n";
    return text;
}

std::string extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

/// "F has N patches but the scene has M" when `expected` (0: any) differs from the `n` a file declares.
void checkPatchCount(const std::string& path, std::uint64_t n, std::size_t expected) {
    if (expected != 0 && n != expected)
        throw Error(path, 0, "F has " + std::to_string(n) + " patches but the scene has " + std::to_string(expected) +
                                 ": it was computed for another scene");
}

class HffWriter {
public:
    explicit HffWriter(std::ostream& out) : m_out(out) {}
    void write(const void* data, std::size_t size) {
        m_sum.add(data, size);
        m_out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    template <class T> void value(const T& v) { write(&v, sizeof(T)); }
    std::uint64_t finish() {
        const std::uint64_t sum = m_sum.value();
        m_out.write(reinterpret_cast<const char*>(&sum), sizeof(sum));
        return sum;
    }

private:
    std::ostream& m_out;
    Checksum m_sum;
};

std::uint64_t saveHff(const FormFactors& F, const std::string& path) {
    checkParameters(withProvenance(F.provenance, F.parameters), path);
    const std::string params = parameterText(F);
    if (params.size() > kMaxParameterBytes)  // what the reader refuses as a corrupt header
        throw Error(path, 0, "parameter text of " + std::to_string(params.size()) + " bytes exceeds the " +
                                 std::to_string(kMaxParameterBytes) + " an .hff file holds");
    AtomicFile file(path);
    HffWriter w(file.stream());
    w.write(kMagic, 8);
    w.value(kVersion);
    w.value(static_cast<std::uint32_t>(params.size()));
    w.value(static_cast<std::uint64_t>(F.size()));
    w.value(static_cast<std::uint64_t>(F.nonZeros()));
    w.value(F.sceneHash);
    w.write(params.data(), params.size());
    w.write(F.computedFlags().data(), F.size());
    w.write(F.rowStarts().data(), F.rowStarts().size() * sizeof(std::uint64_t));
    w.write(F.columns(), F.nonZeros() * sizeof(std::uint32_t));
    w.write(F.values(), F.nonZeros() * sizeof(double));
    const std::uint64_t sum = w.finish();
    file.commit();
    return sum;
}

/// Reads an .hff file section by section, checking sizes before allocating and the checksum at the end.
class HffReader {
public:
    /// Reads from `in`, which holds `bytes` bytes; `path` names it in messages.
    HffReader(std::istream& in, std::uint64_t bytes, const std::string& path) : m_path(path), m_in(in), m_fileBytes(bytes) {}

    FormFactorFileInfo header() {
        if (m_fileBytes < kHeaderBytes + 8)
            fail("truncated: " + std::to_string(m_fileBytes) + " bytes, smaller than the header");
        char magic[8];
        read(magic, 8);
        if (std::memcmp(magic, kMagic, 8) != 0) fail("not a Hemirad F file (bad magic; expected HEMIRADF)");
        FormFactorFileInfo info;
        info.fileBytes = m_fileBytes;
        std::uint32_t paramBytes = 0;
        read(&info.version, 4);
        if (info.version != kVersion && info.version != kFloatVersion)
            fail("unsupported version " + std::to_string(info.version) + " (this build reads versions " +
                 std::to_string(kFloatVersion) + " and " + std::to_string(kVersion) + ")");
        read(&paramBytes, 4);
        read(&info.size, 8);
        read(&info.nonZeros, 8);
        read(&info.sceneHash, 8);
        if (paramBytes > kMaxParameterBytes) fail("corrupt header: parameter text of " + std::to_string(paramBytes) + " bytes");
        if (info.size > std::uint64_t(kMaxPatches)) fail("corrupt header: N = " + std::to_string(info.size));
        if (info.size > 0 && info.nonZeros / info.size > info.size)
            fail("corrupt header: nnz = " + std::to_string(info.nonZeros) + " exceeds N^2 for N = " + std::to_string(info.size));
        const std::uint64_t expected =
            kHeaderBytes + paramBytes + info.size + 8 * (info.size + 1) + (4 + valueBytes(info.version)) * info.nonZeros + 8;
        if (m_fileBytes < expected)
            fail("truncated: " + std::to_string(m_fileBytes) + " bytes, the header announces " + std::to_string(expected));
        if (m_fileBytes > expected)
            fail("corrupt: " + std::to_string(m_fileBytes) + " bytes, the header announces " + std::to_string(expected));
        std::string params(paramBytes, '\0');
        read(params.data(), paramBytes);
        std::istringstream lines(params);
        std::string line;
        while (std::getline(lines, line)) {
            const std::size_t eq = line.find('=');
            if (eq == std::string::npos) fail("corrupt parameter text " + quote(line));
            info.parameters[line.substr(0, eq)] = line.substr(eq + 1);
        }
        return info;
    }

    template <class T> std::vector<T> array(std::uint64_t count) {
        std::vector<T> v(count);
        read(v.data(), count * sizeof(T));
        return v;
    }

    /// Returns the checksum, verified.
    std::uint64_t checkChecksum() {
        const std::uint64_t computed = m_sum.value();
        std::uint64_t stored = 0;
        m_in.read(reinterpret_cast<char*>(&stored), 8);
        if (!m_in) fail("truncated before the checksum");
        if (stored != computed) fail("checksum mismatch: the file is corrupt");
        return stored;
    }

    /// Reads `count` elements of which only [first, last) are kept (the rest hashed and dropped).
    template <class T> std::vector<T> slice(std::uint64_t count, std::uint64_t first, std::uint64_t last) {
        skip(first * sizeof(T));
        std::vector<T> kept = array<T>(last - first);
        skip((count - last) * sizeof(T));
        return kept;
    }

    /// Skips the arrays (hashing them) and checks the checksum; for `hemirad info`.
    void skipArrays(const FormFactorFileInfo& info, std::size_t& computedRows) {
        auto flags = array<std::uint8_t>(info.size);
        computedRows = static_cast<std::size_t>(std::count(flags.begin(), flags.end(), 1));
        skip(8 * (info.size + 1) + (4 + valueBytes(info.version)) * info.nonZeros);
        checkChecksum();
    }

    [[noreturn]] void fail(const std::string& message) const { throw Error(m_path, 0, message); }

private:
    void read(void* data, std::size_t size) {
        m_in.read(static_cast<char*>(data), static_cast<std::streamsize>(size));
        if (!m_in) fail("truncated or unreadable");
        m_sum.add(data, size);
    }

    /// Reads `bytes` into the checksum alone, 64 KiB at a time.
    void skip(std::uint64_t bytes) {
        std::vector<char> buffer(std::size_t(std::min<std::uint64_t>(bytes, 1 << 16)));
        while (bytes > 0) {
            const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(bytes, buffer.size()));
            read(buffer.data(), n);
            bytes -= n;
        }
    }

    std::string m_path;
    std::istream& m_in;
    std::uint64_t m_fileBytes = 0;
    Checksum m_sum;
};

/// An .hff file opened for HffReader, with its size.
struct HffFile {
    std::ifstream stream;
    std::uint64_t bytes = 0;
    explicit HffFile(const std::string& path) {
        std::error_code ec;
        if (std::filesystem::is_directory(path, ec)) throw Error(path, 0, "is a directory, not an F file");
        stream.open(path, std::ios::binary);
        if (!stream) throw Error(path, 0, std::string("cannot open: ") + std::strerror(errno));
        stream.seekg(0, std::ios::end);
        bytes = static_cast<std::uint64_t>(stream.tellg());
        stream.seekg(0);
    }
};

/// F of the file's N holding its rows [first, last) (clamped to N) alone: every row start and flag
/// is checked, the kept rows' columns and values too, and every byte goes into the checksum.
FormFactors readHff(HffReader& r, const std::string& path, std::uint64_t* checksum = nullptr,
                    std::size_t expectedPatches = 0, std::uint64_t first = 0, std::uint64_t last = ~std::uint64_t(0)) {
    const FormFactorFileInfo info = r.header();
    const std::uint64_t n = info.size, nnz = info.nonZeros;
    checkPatchCount(path, n, expectedPatches);
    last = std::min(last, n);
    first = std::min(first, last);
    auto computed = r.array<std::uint8_t>(n);
    auto rowStart = r.array<std::uint64_t>(n + 1);
    // The kept rows' entries [begin, end) (within nnz until the row starts are checked).
    const std::uint64_t begin = std::min(rowStart[first], nnz), end = std::clamp(rowStart[last], begin, nnz);
    auto columns = r.slice<std::uint32_t>(nnz, begin, end);
    std::vector<double> values;
    if (info.version == kFloatVersion) {
        const auto stored = r.slice<float>(nnz, begin, end);
        values.assign(stored.begin(), stored.end());
    } else {
        values = r.slice<double>(nnz, begin, end);
    }
    const std::uint64_t sum = r.checkChecksum();
    if (checksum) *checksum = sum;
    if (rowStart[0] != 0 || rowStart[n] != nnz) r.fail("corrupt row starts (first must be 0, last nnz)");
    for (std::uint64_t i = 0; i < n; ++i) {
        if (computed[i] > 1) r.fail("corrupt computed-row flag " + std::to_string(computed[i]) + " for row " + std::to_string(i));
        if (rowStart[i + 1] < rowStart[i] || rowStart[i + 1] > nnz)
            r.fail("corrupt row starts at row " + std::to_string(i));
        if (!computed[i] && rowStart[i + 1] != rowStart[i])
            r.fail("row " + std::to_string(i) + " is marked skipped but has entries");
    }
    // Rows before the kept ones start at 0, rows after them are empty and not computed.
    for (std::uint64_t i = 0; i <= n; ++i) rowStart[i] = std::clamp(rowStart[i], begin, end) - begin;
    for (std::uint64_t i = 0; i < n; ++i) {
        if (i < first || i >= last) computed[i] = 0;
        for (std::uint64_t k = rowStart[i]; k < rowStart[i + 1]; ++k) {
            if (columns[k] >= n)
                r.fail("column " + std::to_string(columns[k]) + " in row " + std::to_string(i) + " is out of range (N = " +
                       std::to_string(n) + ")");
            if (k > rowStart[i] && columns[k] <= columns[k - 1])
                r.fail("columns of row " + std::to_string(i) + " are not strictly increasing");
        }
    }
    FormFactors F = FormFactors::fromCsr(std::move(rowStart), std::move(columns), std::move(values), std::move(computed));
    F.sceneHash = info.sceneHash;
    F.parameters = info.parameters;
    F.provenance = takeProvenance(F.parameters, path);
    validateFormFactors(F, n, path, rowSumBound(F));
    return F;
}

void appendRanges(std::ostream& out, const FormFactors& F) {
    std::size_t written = 0;
    for (std::size_t i = 0; i < F.size();) {
        if (F.rowComputed(i)) {
            ++i;
            continue;
        }
        std::size_t j = i;
        while (j + 1 < F.size() && !F.rowComputed(j + 1)) ++j;
        if (written % 16 == 0) out << (written ? "\n" : "") << "% hemirad skipped_rows";
        out << ' ' << i;
        if (j > i) out << '-' << j;
        ++written;
        i = j + 1;
    }
    if (written) out << '\n';
}

void saveMtx(const FormFactors& F, const std::string& path) {
    checkParameters(withProvenance(F.provenance, F.parameters), path);
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    out << "%%MatrixMarket matrix coordinate real general\n"
        << "% Hemirad form factors: row i = emitting patch, column j = receiving patch, value F_ij (1-based)\n"
        << "% hemirad scene_hash " << hexHash(F.sceneHash) << '\n';
    for (const auto& [key, value] : withProvenance(F.provenance, F.parameters))
        out << "% hemirad param " << key << ' ' << value << '\n';
    appendRanges(out, F);
    out << F.size() << ' ' << F.size() << ' ' << F.nonZeros() << '\n';
    // Each line fits in 70 characters (two 20-digit integers, a shortest-round-trip double).
    char buffer[128];
    char* const limit = buffer + 100;
    for (std::size_t i = 0; i < F.size(); ++i)
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            char* p = std::to_chars(buffer, limit, i + 1).ptr;
            *p++ = ' ';
            p = std::to_chars(p, limit, F.columns()[k] + 1).ptr;
            *p++ = ' ';
            p = std::to_chars(p, limit, F.values()[k]).ptr;
            *p++ = '\n';
            out.write(buffer, p - buffer);
        }
    file.commit();
}

/// An .mtx file read and checked entry by entry before anything of size N exists: what it costs
/// follows what it holds (its text, entries and skipped ranges), never the N it declares (68 bytes
/// may declare 2^28 patches, whose row arrays alone take 2.3 GB).
struct MtxContents {
    struct Entry {
        std::uint32_t row, column;
        double value;
    };
    std::uint64_t n = 0;
    std::uint64_t sceneHash = 0;
    FormFactorProvenance provenance;
    std::map<std::string, std::string> parameters;             ///< without the provenance's keys
    std::vector<std::pair<std::uint64_t, std::uint64_t>> skipped;  ///< rows [a, b], sorted, disjoint
    std::vector<Entry> entries;                                    ///< by row then column, unique

    std::uint64_t skippedRows() const {
        std::uint64_t rows = 0;
        for (const auto& [a, b] : skipped) rows += b - a + 1;
        return rows;
    }
};

/// Reads and checks every entry (range, value, skipped rows, count, duplicates, row sums against the
/// provenance's bound) as loadFormFactors does. `expectedPatches` (0: any) is checked at the size line.
MtxContents readMtx(const std::string& path, std::string_view text, std::size_t expectedPatches) {
    TextReader r(path, text);
    if (!r.next() || r.tokens().size() < 5 || r.tokens()[0] != "%%MatrixMarket")
        throw Error(path, 1, "not a Matrix Market file (expected '%%MatrixMarket matrix coordinate real general')");
    const auto& h = r.tokens();
    if (h[1] != "matrix" || h[2] != "coordinate" || (h[3] != "real" && h[3] != "double") || h[4] != "general")
        r.fail("unsupported Matrix Market type " + quote(r.rest(1)) + "; expected 'matrix coordinate real general'");
    MtxContents c;
    bool haveHash = false;
    std::uint64_t nnz = 0;
    while (r.next()) {
        const auto& t = r.tokens();
        if (t.empty()) continue;
        if (t[0][0] == '%') {
            if (t.size() >= 3 && t[0] == "%" && t[1] == "hemirad") {
                if (t[2] == "scene_hash" && t.size() == 4) {
                    const std::string hex(t[3]);
                    char* end = nullptr;
                    c.sceneHash = std::strtoull(hex.c_str(), &end, 16);
                    if (*end != '\0') r.fail("bad scene hash " + quote(hex));
                    haveHash = true;
                } else if (t[2] == "param" && t.size() >= 4) {
                    c.parameters[std::string(t[3])] = t.size() > 4 ? r.rest(4) : "";
                } else if (t[2] == "skipped_rows") {
                    for (std::size_t k = 3; k < t.size(); ++k) {
                        const std::string range(t[k]);
                        char* end = nullptr;
                        const std::uint64_t a = std::strtoull(range.c_str(), &end, 10);
                        std::uint64_t b = a;
                        if (*end == '-') b = std::strtoull(end + 1, &end, 10);
                        if (*end != '\0' || b < a) r.fail("bad skipped row range " + quote(range));
                        c.skipped.emplace_back(a, b);
                    }
                }
            }
            continue;
        }
        if (t.size() != 3) r.fail("size line needs 'rows columns entries'");
        const long rows = r.integer(0, "row count"), cols = r.integer(1, "column count"), entries = r.integer(2, "entry count");
        if (rows <= 0 || rows != cols) r.fail("F must be square with N > 0; found " + std::to_string(rows) + " x " + std::to_string(cols));
        if (rows > kMaxPatches) r.fail("N = " + std::to_string(rows) + " is more patches than Hemirad handles (" + std::to_string(kMaxPatches) + ")");
        // Every entry takes at least 6 characters ("1 1 0\n"): a count the text cannot hold is corrupt.
        if (entries < 0 || static_cast<double>(entries) > static_cast<double>(rows) * rows ||
            static_cast<double>(entries) * 6.0 > static_cast<double>(text.size()))
            r.fail("entry count " + std::to_string(entries) + " is impossible for N = " + std::to_string(rows) + " in " +
                   std::to_string(text.size()) + " bytes");
        c.n = static_cast<std::uint64_t>(rows);
        nnz = static_cast<std::uint64_t>(entries);
        break;
    }
    if (c.n == 0) throw Error(path, r.line(), "no size line");
    checkPatchCount(path, c.n, expectedPatches);
    // Skipped ranges sorted and merged (overlaps allowed): as many as the file lists, not N.
    for (const auto& [a, b] : c.skipped)
        if (b >= c.n) throw Error(path, 0, "skipped row " + std::to_string(b) + " is out of range (N = " + std::to_string(c.n) + ")");
    std::sort(c.skipped.begin(), c.skipped.end());
    std::size_t merged = 0;
    for (const auto& range : c.skipped) {
        if (merged > 0 && range.first <= c.skipped[merged - 1].second + 1)
            c.skipped[merged - 1].second = std::max(c.skipped[merged - 1].second, range.second);
        else
            c.skipped[merged++] = range;
    }
    c.skipped.resize(merged);
    const auto isSkipped = [&c](std::uint64_t row) {
        auto it = std::upper_bound(c.skipped.begin(), c.skipped.end(), std::make_pair(row, ~std::uint64_t(0)));
        return it != c.skipped.begin() && std::prev(it)->second >= row;
    };
    c.entries.reserve(nnz);  // at most one per 6 bytes of the text (checked above)
    while (r.next()) {
        const auto& t = r.tokens();
        if (t.empty() || t[0][0] == '%') continue;
        if (t.size() != 3) r.fail("entry needs 'row column value', found " + std::to_string(t.size()) + " fields");
        const long i = r.integer(0, "row"), j = r.integer(1, "column");
        const double v = r.number(2, "value");
        if (i < 1 || i > static_cast<long>(c.n) || j < 1 || j > static_cast<long>(c.n))
            r.fail("entry (" + std::to_string(i) + ", " + std::to_string(j) + ") is outside 1.." + std::to_string(c.n));
        if (v < 0.0 || v > 3.4e38) r.fail("F value " + quote(t[2]) + " is " + (v < 0.0 ? "negative" : "out of range"));
        if (isSkipped(std::uint64_t(i - 1))) r.fail("row " + std::to_string(i) + " has entries but is listed as skipped");
        if (c.entries.size() >= nnz) r.fail("more entries than the " + std::to_string(nnz) + " announced");
        c.entries.push_back({static_cast<std::uint32_t>(i - 1), static_cast<std::uint32_t>(j - 1), v});
    }
    if (c.entries.size() < nnz)
        throw Error(path, r.line(), "truncated: " + std::to_string(c.entries.size()) + " of " + std::to_string(nnz) + " entries");
    std::sort(c.entries.begin(), c.entries.end(), [](const MtxContents::Entry& a, const MtxContents::Entry& b) {
        return a.row != b.row ? a.row < b.row : a.column < b.column;
    });
    for (std::size_t k = 1; k < c.entries.size(); ++k)
        if (c.entries[k].row == c.entries[k - 1].row && c.entries[k].column == c.entries[k - 1].column)
            throw Error(path, 0, "duplicate entry (" + std::to_string(c.entries[k].row + 1) + ", " +
                                     std::to_string(c.entries[k].column + 1) + ")");
    c.provenance = takeProvenance(c.parameters, path);
    if (!haveHash) c.provenance.sceneHashKnown = false;  // a foreign .mtx: only its size can be checked
    // Row sums, as validateFormFactors checks them on a loaded F (values are finite and >= 0 already).
    const double bound = rowSumBound(c.provenance);
    for (std::size_t k = 0; k < c.entries.size();) {
        const std::uint32_t row = c.entries[k].row;
        double sum = 0.0;
        for (; k < c.entries.size() && c.entries[k].row == row; ++k) sum += c.entries[k].value;
        if (sum > bound) {
            std::ostringstream msg;
            msg << "row " << row << " of F sums to " << sum << ", above the bound " << bound
                << ": more power arrives than leaves";
            throw Error(path, 0, msg.str());
        }
    }
    return c;
}

/// F in CSR from checked contents: the N-sized row arrays are allocated here, once the file has
/// shown that it is whole.
FormFactors toFormFactors(MtxContents&& c, const std::string& path) {
    std::vector<std::uint8_t> computed(c.n, 1);
    for (const auto& [a, b] : c.skipped)
        std::fill(computed.begin() + std::ptrdiff_t(a), computed.begin() + std::ptrdiff_t(b + 1), std::uint8_t(0));
    std::vector<std::uint64_t> rowStart(c.n + 1, 0);
    std::vector<std::uint32_t> columns(c.entries.size());
    std::vector<double> values(c.entries.size());
    for (std::size_t k = 0; k < c.entries.size(); ++k) {
        ++rowStart[c.entries[k].row + 1];
        columns[k] = c.entries[k].column;
        values[k] = c.entries[k].value;
    }
    std::vector<MtxContents::Entry>().swap(c.entries);
    for (std::uint64_t i = 0; i < c.n; ++i) rowStart[i + 1] += rowStart[i];
    FormFactors F = FormFactors::fromCsr(std::move(rowStart), std::move(columns), std::move(values), std::move(computed));
    F.sceneHash = c.sceneHash;
    F.parameters = std::move(c.parameters);
    F.provenance = c.provenance;
    validateFormFactors(F, c.n, path, rowSumBound(F));
    return F;
}

FormFactors parseMtx(const std::string& path, std::string_view text, std::size_t expectedPatches = 0) {
    return toFormFactors(readMtx(path, text, expectedPatches), path);
}

}  // namespace

std::string hexHash(std::uint64_t hash) {
    char buffer[17];
    std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(hash));
    return buffer;
}

FormFactorFormat formFactorFormatFor(const std::string& path) {
    const std::string ext = extension(path);
    if (ext == ".hff") return FormFactorFormat::Hff;
    if (ext == ".mtx") return FormFactorFormat::Mtx;
    if (isStandardOutput(path)) return FormFactorFormat::Mtx;
    if (writesInPlace(path)) return FormFactorFormat::Hff;
    throw Error(path, 0, "unknown F file type " + quote(ext) + " (use .hff or .mtx)");
}

void saveFormFactors(const FormFactors& F, const std::string& path, FormFactorFormat format) {
    // A manifest this file replaces: its shards go once the new file is in place, and so do shards
    // an interrupted sharded write left beside it. A target written in place has no folder of its own.
    const bool beside = !isStandardOutput(path) && !writesInPlace(path);
    const std::vector<std::string> shards = beside ? listedShardFiles(path) : std::vector<std::string>{};
    if (format == FormFactorFormat::Hff) saveHff(F, path);
    else saveMtx(F, path);
    if (beside) removeReplacedShards(path, shards);
}

void saveFormFactors(const FormFactors& F, const std::string& path) {
    saveFormFactors(F, path, formFactorFormatFor(path));
}

std::uint64_t saveHffFile(const FormFactors& F, const std::string& path) { return saveHff(F, path); }

FormFactors loadHffFile(const std::string& path, std::uint64_t& checksum) {
    HffFile file(path);
    HffReader r(file.stream, file.bytes, path);
    return readHff(r, path, &checksum);
}

HffRowIndex readHffRowIndex(const std::string& path, std::size_t expectedPatches) {
    HffFile file(path);
    HffReader r(file.stream, file.bytes, path);
    const FormFactorFileInfo info = r.header();
    checkPatchCount(path, info.size, expectedPatches);
    HffRowIndex index;
    index.computed = r.array<std::uint8_t>(info.size);
    index.lengths = r.array<std::uint64_t>(info.size + 1);
    std::vector<std::uint64_t>& lengths = index.lengths;
    for (std::uint64_t i = 0; i < info.size; ++i) {
        if (lengths[i + 1] < lengths[i] || lengths[i + 1] > info.nonZeros)
            r.fail("corrupt row starts at row " + std::to_string(i));
        lengths[i] = lengths[i + 1] - lengths[i];
    }
    lengths.pop_back();
    return index;
}

FormFactors loadHffRows(const std::string& path, std::size_t first, std::size_t last, std::size_t expectedPatches) {
    HffFile file(path);
    HffReader r(file.stream, file.bytes, path);
    return readHff(r, path, nullptr, expectedPatches, first, last);
}

FormFactors loadFormFactors(const std::string& path, std::size_t expectedPatches) {
    const std::string ext = extension(path);
    if (ext == ".hff" && isShardManifest(path)) {
        checkPatchCount(path, readShardManifest(path).patches, expectedPatches);
        return loadShardedFormFactors(path);
    }
    if (ext == ".hff") {
        HffFile file(path);
        HffReader r(file.stream, file.bytes, path);
        return readHff(r, path, nullptr, expectedPatches);
    }
    if (ext == ".mtx") return parseMtx(path, readTextFile(path), expectedPatches);
    throw Error(path, 0, "unknown F file type " + quote(ext) + " (use .hff or .mtx)");
}

FormFactors parseFormFactors(const std::string& name, const std::string& bytes) {
    const std::string ext = extension(name);
    if (ext == ".hff") {
        std::istringstream in(bytes);
        HffReader r(in, bytes.size(), name);
        return readHff(r, name);
    }
    if (ext == ".mtx") return parseMtx(name, bytes);
    throw Error(name, 0, "unknown F file type " + quote(ext) + " (use .hff or .mtx)");
}

FormFactorFileInfo readFormFactorInfo(const std::string& path) {
    if (extension(path) == ".mtx") {  // described from its entries: nothing of size N
        const std::string text = readTextFile(path);
        const MtxContents c = readMtx(path, text, 0);
        FormFactorFileInfo info;
        info.size = c.n;
        info.nonZeros = c.entries.size();
        info.sceneHash = c.sceneHash;
        info.computedRows = static_cast<std::size_t>(c.n - c.skippedRows());
        info.parameters = c.parameters;
        info.fileBytes = text.size();
        MtxRowSums sums;
        sums.provenance = c.provenance;
        for (std::size_t k = 0; k < c.entries.size();) {
            const std::uint32_t row = c.entries[k].row;
            double sum = 0.0;
            for (; k < c.entries.size() && c.entries[k].row == row; ++k) {
                sum += c.entries[k].value;
                if (c.entries[k].column == row && c.entries[k].value > 0.0f) ++sums.selfFactorRows;
            }
            sums.min = std::min(sums.min, sum);
            sums.max = std::max(sums.max, sum);
            sums.total += sum;
            ++sums.rowsWithEntries;
        }
        if (info.computedRows > sums.rowsWithEntries) sums.min = std::min(sums.min, 0.0);  // computed rows with no entry
        info.mtxRows = sums;
        return info;
    }
    HffFile file(path);
    HffReader r(file.stream, file.bytes, path);
    FormFactorFileInfo info = r.header();
    r.skipArrays(info, info.computedRows);
    return info;
}

void checkFormFactorsMatch(const FormFactors& F, std::uint64_t sceneHash, std::size_t patchCount,
                           const std::string& path) {
    if (F.size() != patchCount)
        throw Error(path, 0, "F has " + std::to_string(F.size()) + " patches but the scene has " +
                                 std::to_string(patchCount) + ": it was computed for another scene");
    if (!F.provenance.sceneHashKnown) return;  // foreign .mtx: size checked only
    if (F.sceneHash != sceneHash)
        throw Error(path, 0, "F was computed for another scene (scene hash " + hexHash(F.sceneHash) + ", this scene " +
                                 hexHash(sceneHash) + "): geometry or mirror reflectance changed; recompute it");
}

}  // namespace hemirad
