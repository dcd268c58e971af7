// F files: round trips in both formats and a clear error for every kind of damage.
#include "support.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/form_factor_shards.hpp"
#include "engine/scene_loader.hpp"
#include "engine/subdivide.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// A 4-patch F with a skipped row, a self factor and awkward values (no float holds 0.1, 1/3 or 1e-7).
FormFactors sampleF() {
    std::vector<std::vector<FormFactors::Entry>> rows(4);
    rows[0] = {{1, 0.25}, {2, 0.1}, {3, 1.0 / 3.0}};
    rows[1] = {{0, 0.5}, {1, 1e-7}};
    rows[3] = {{0, 0.125}, {2, 0.875}};
    FormFactors F = FormFactors::fromRows(std::move(rows), {1, 1, 0, 1});
    F.sceneHash = 0x0123456789abcdefULL;
    F.provenance.method = "hemisphere";
    F.provenance.estimator = "analytic";
    F.provenance.rowSumBound = 1.9;
    F.parameters = {{"samples", "96"}, {"estimator", "analytic: Lambert factors, described for people"}};
    return F;
}

void requireSame(const FormFactors& a, const FormFactors& b) {
    REQUIRE(a.size() == b.size());
    REQUIRE(a.nonZeros() == b.nonZeros());
    CHECK(a.sceneHash == b.sceneHash);
    for (std::size_t i = 0; i < a.size(); ++i) {
        CHECK(a.rowComputed(i) == b.rowComputed(i));
        REQUIRE(a.rowBegin(i) == b.rowBegin(i));
        for (std::uint64_t k = a.rowBegin(i); k < a.rowEnd(i); ++k) {
            CHECK(a.columns()[k] == b.columns()[k]);
            CHECK(a.values()[k] == b.values()[k]);  // bit-exact: shortest round-trip text in .mtx
        }
    }
}

std::string readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST_CASE("F file round-trip keeps every entry (.hff and .mtx)") {
    const auto dir = tempDir("ff");
    const FormFactors F = sampleF();
    for (const char* name : {"F.hff", "F.mtx"}) {
        const std::string path = (dir / name).string();
        saveFormFactors(F, path);
        const FormFactors G = loadFormFactors(path);
        requireSame(F, G);
        CHECK(G.provenance == F.provenance);
        CHECK(G.parameters == F.parameters);
    }
    const FormFactorFileInfo info = readFormFactorInfo((dir / "F.hff").string());
    CHECK(info.size == 4);
    CHECK(info.nonZeros == 7);
    CHECK(info.computedRows == 3);
    CHECK_FALSE(info.mtxRows.has_value());
    // An .mtx is described from its entries alone: the same figures as the loaded F gives.
    const FormFactorFileInfo text = readFormFactorInfo((dir / "F.mtx").string());
    CHECK(text.size == 4);
    CHECK(text.nonZeros == 7);
    CHECK(text.computedRows == 3);
    CHECK(text.sceneHash == F.sceneHash);
    REQUIRE(text.mtxRows.has_value());
    CHECK(text.mtxRows->provenance == F.provenance);
    CHECK(text.mtxRows->rowsWithEntries == 3);
    CHECK(text.mtxRows->selfFactorRows == 1);  // F(1, 1) = 1e-7
    CHECK(text.mtxRows->min == doctest::Approx(F.rowSum(1)));
    CHECK(text.mtxRows->max == doctest::Approx(F.rowSum(3)));
    CHECK(text.mtxRows->total == doctest::Approx(F.rowSum(0) + F.rowSum(1) + F.rowSum(3)));
    // A load for a scene of another size is refused before F is built, in every format.
    for (const char* name : {"F.hff", "F.mtx"}) {
        const std::string message = std::string(name) + ": F has 4 patches but the scene has 5";
        CHECK_THROWS_WITH_AS(loadFormFactors((dir / name).string(), 5), doctest::Contains(message.c_str()), Error);
    }
    CHECK(loadFormFactors((dir / "F.mtx").string(), 4).size() == 4);
}

TEST_CASE("F's provenance is typed in memory and stored under readable keys, and old and foreign files load") {
    const auto dir = tempDir("ff-provenance");
    // The keys an F file holds for people and for the typed provenance (as written before it was typed).
    const FormFactors F = sampleF();
    saveFormFactors(F, (dir / "F.mtx").string());
    const std::string text = readAll((dir / "F.mtx").string());
    CHECK(text.find("% hemirad param method hemisphere\n") != std::string::npos);
    CHECK(text.find("% hemirad param row_sum_bound 1.9\n") != std::string::npos);
    CHECK(text.find("% hemirad param estimator analytic: Lambert factors, described for people\n") != std::string::npos);
    // A file written before provenance was typed, with the rays estimator's bare kind.
    const std::string old = "%%MatrixMarket matrix coordinate real general\n% hemirad scene_hash 0123456789abcdef\n"
                            "% hemirad param estimator rays\n% hemirad param method hemisphere\n"
                            "% hemirad param row_sum_bound 1\n% hemirad param samples 96\n2 2 1\n1 2 0.5\n";
    const FormFactors O = parseFormFactors("old.mtx", old);
    CHECK(O.provenance.method == "hemisphere");
    CHECK(O.provenance.estimator == "rays");
    CHECK(O.provenance.rowSumBound == 1.0);
    CHECK(O.provenance.sceneHashKnown);
    CHECK(O.parameters == std::map<std::string, std::string>{{"samples", "96"}});
    // A foreign .mtx (scipy, another code): no hash, no method; only its size can be checked.
    const FormFactors foreign = parseFormFactors("foreign.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 2 0.5\n");
    CHECK_FALSE(foreign.provenance.sceneHashKnown);
    CHECK(foreign.provenance.method.empty());
    CHECK_NOTHROW(checkFormFactorsMatch(foreign, 0xfeed, 2, "foreign.mtx"));
    CHECK_THROWS_WITH_AS(checkFormFactorsMatch(foreign, 0xfeed, 3, "foreign.mtx"), doctest::Contains("F has 2 patches"), Error);
    // Stored again, it stays unverifiable (scene_hash unknown), not "known with hash 0".
    saveFormFactors(foreign, (dir / "again.hff").string());
    CHECK_FALSE(loadFormFactors((dir / "again.hff").string()).provenance.sceneHashKnown);
    // A bound that is not a number >= 1 is an error naming the file.
    const std::string bad = "%%MatrixMarket matrix coordinate real general\n% hemirad param row_sum_bound lots\n2 2 1\n1 2 0.5\n";
    CHECK_THROWS_WITH_AS(parseFormFactors("bad.mtx", bad), doctest::Contains("bad.mtx: bad parameter row_sum_bound 'lots'"),
                         Error);
}

TEST_CASE("F memory is about 12 bytes per nonzero") {
    const FormFactors F = sampleF();
    CHECK(F.memoryBytes() == 7 * 12 + 5 * 8 + 4);
}

TEST_CASE("F's values are doubles in .hff (version 2) and .mtx, and a version 1 .hff (float values) still loads") {
    const auto dir = tempDir("ff-double");
    const FormFactors F = sampleF();
    for (const char* name : {"F.hff", "F.mtx"}) {
        CAPTURE(name);
        const std::string path = (dir / name).string();
        saveFormFactors(F, path);
        const FormFactors G = loadFormFactors(path);
        CHECK(G.at(0, 2) == 0.1);  // not float(0.1) = 0.100000001490116
        CHECK(G.at(0, 2) != double(0.1f));
        CHECK(G.at(0, 3) == 1.0 / 3.0);
        CHECK(G.at(1, 1) == 1e-7);
    }
    CHECK(readFormFactorInfo((dir / "F.hff").string()).version == 2);
    CHECK(readFormFactorInfo((dir / "F.hff").string()).fileBytes ==
          std::filesystem::file_size(dir / "F.hff"));
    // perpendicular_plates_v1.hff: `hemirad formfactors scenes/perpendicular_plates.obj` at 899544d,
    // when F's values were float (2 patches, 2 entries).
    const std::string old = sourcePath("tests/data/perpendicular_plates_v1.hff");
    CHECK(readFormFactorInfo(old).version == 1);
    const FormFactors V1 = loadFormFactors(old);
    REQUIRE(V1.size() == 2);
    REQUIRE(V1.nonZeros() == 2);
    Warnings warnings = quietWarnings();
    const Scene plates = loadScene(sourcePath("scenes/perpendicular_plates.obj"), warnings);
    CHECK(V1.sceneHash == plates.geometryHash());
    // Its exact factors (Howell C-14: a 1 x 1 plate and a 2 x 1 one on a common edge of 1), each
    // rounded to float.
    const double expected[2] = {c14(1, 2, 1), c14(1, 2, 1) / 2};
    for (PatchId i = 0; i < 2; ++i) {
        CHECK(V1.at(i, 1 - i) == double(float(V1.at(i, 1 - i))));  // a float, widened
        CHECK(V1.at(i, 1 - i) == relative(expected[i], 1e-7));
    }
    // Rewritten, it is a version 2 file with the same values.
    saveFormFactors(V1, (dir / "again.hff").string());
    CHECK(readFormFactorInfo((dir / "again.hff").string()).version == 2);
    requireSame(V1, loadFormFactors((dir / "again.hff").string()));
}

TEST_CASE("A damaged .hff file fails with a clear message") {
    const auto dir = tempDir("ff-bad");
    const std::string good = (dir / "good.hff").string();
    saveFormFactors(sampleF(), good);
    const std::string bytes = readAll(good);
    auto damaged = [&](const std::string& name, std::string content) {
        return writeFile(dir / name, content);
    };

    SUBCASE("truncated inside every section") {
        // header, parameters, flags, row starts, columns, values, checksum
        for (std::size_t cut : {std::size_t(10), std::size_t(41), std::size_t(70), std::size_t(100), bytes.size() - 40,
                                bytes.size() - 12, bytes.size() - 3}) {
            CAPTURE(cut);
            CHECK_THROWS_WITH_AS(loadFormFactors(damaged("cut.hff", bytes.substr(0, cut))),
                                 doctest::Contains("truncated"), Error);
        }
    }
    SUBCASE("bad magic") {
        std::string b = bytes;
        b[0] = 'X';
        CHECK_THROWS_WITH_AS(loadFormFactors(damaged("magic.hff", b)), doctest::Contains("bad magic"), Error);
    }
    SUBCASE("unknown version") {
        std::string b = bytes;
        b[8] = 9;
        CHECK_THROWS_WITH_AS(loadFormFactors(damaged("version.hff", b)), doctest::Contains("unsupported version 9"), Error);
    }
    SUBCASE("a flipped bit in the values fails the checksum") {
        std::string b = bytes;
        b[b.size() - 12] ^= 0x10;
        CHECK_THROWS_WITH_AS(loadFormFactors(damaged("flip.hff", b)), doctest::Contains("checksum mismatch"), Error);
    }
    SUBCASE("inconsistent N or nnz") {
        std::string b = bytes;
        b[24] = 10;  // nnz
        CHECK_THROWS_WITH_AS(loadFormFactors(damaged("nnz.hff", b)), doctest::Contains("truncated"), Error);
        b[24] = 99;
        CHECK_THROWS_WITH_AS(loadFormFactors(damaged("nnz.hff", b)),
                             doctest::Contains("corrupt header: nnz = 99 exceeds N^2"), Error);
        b = bytes;
        b[16] = 2;  // N
        CHECK_THROWS_WITH_AS(loadFormFactors(damaged("n.hff", b)), doctest::Contains("corrupt"), Error);
    }
    SUBCASE("not a file") {
        CHECK_THROWS_WITH_AS(loadFormFactors((dir / "none.hff").string()), doctest::Contains("cannot open"), Error);
        CHECK_THROWS_WITH_AS(loadFormFactors(dir.string() + "/x.bin"), doctest::Contains("unknown F file type"), Error);
    }
}

TEST_CASE("A range of rows read alone from an .hff file holds those rows only, and the whole file is checksummed") {
    // issue 35 #12: each MPI rank reads its share of a reused F's rows, not all of F.
    const auto dir = tempDir("ff-rows");
    const FormFactors F = sampleF();
    const std::string path = (dir / "F.hff").string();
    saveFormFactors(F, path);
    const FormFactors rows = loadHffRows(path, 1, 3, 4);  // row 1 and the skipped row 2
    REQUIRE(rows.size() == 4);
    CHECK(rows.nonZeros() == 2);
    CHECK(rows.sceneHash == F.sceneHash);
    CHECK(rows.provenance == F.provenance);
    CHECK(rows.parameters == F.parameters);
    for (std::size_t i = 0; i < 4; ++i) {
        CAPTURE(i);
        CHECK(rows.rowComputed(i) == (i == 1));
        REQUIRE(rows.rowEnd(i) - rows.rowBegin(i) == (i == 1 ? F.rowEnd(i) - F.rowBegin(i) : 0));
        for (std::uint64_t k = 0; k < rows.rowEnd(i) - rows.rowBegin(i); ++k) {
            CHECK(rows.columns()[rows.rowBegin(i) + k] == F.columns()[F.rowBegin(i) + k]);
            CHECK(rows.values()[rows.rowBegin(i) + k] == F.values()[F.rowBegin(i) + k]);
        }
    }
    // Every row, an empty range, and a range past N (clamped).
    requireSame(loadHffRows(path, 0, 4), F);
    CHECK(loadHffRows(path, 2, 2).nonZeros() == 0);
    CHECK(loadHffRows(path, 3, 99).nonZeros() == 2);
    CHECK_THROWS_WITH_AS(loadHffRows(path, 0, 4, 5), doctest::Contains("F has 4 patches but the scene has 5"), Error);
    // A flipped bit in the last row's values, outside the rows read: the checksum still refuses it.
    std::string bytes = readAll(path);
    bytes[bytes.size() - 12] ^= 0x10;
    writeFile(dir / "flip.hff", bytes);
    CHECK_THROWS_WITH_AS(loadHffRows((dir / "flip.hff").string(), 0, 1), doctest::Contains("checksum mismatch"), Error);
}

TEST_CASE("Well-formed files with impossible content are rejected") {
    const auto dir = tempDir("ff-content");
    SUBCASE("column out of range") {
        FormFactors F = FormFactors::fromCsr({0, 1, 1}, {5}, {0.5f}, {1, 1});
        saveFormFactors(F, (dir / "col.hff").string());
        CHECK_THROWS_WITH_AS(loadFormFactors((dir / "col.hff").string()),
                             doctest::Contains("column 5 in row 0 is out of range (N = 2)"), Error);
    }
    SUBCASE("NaN value") {
        FormFactors F = FormFactors::fromCsr({0, 1, 1}, {1}, {std::nanf("")}, {1, 1});
        saveFormFactors(F, (dir / "nan.hff").string());
        CHECK_THROWS_WITH_AS(loadFormFactors((dir / "nan.hff").string()),
                             doctest::Contains("F(0, 1) = nan is not a finite non-negative number"), Error);
    }
    SUBCASE("row sum above one") {
        FormFactors F = FormFactors::fromCsr({0, 2, 2}, {0, 1}, {0.7f, 0.7f}, {1, 1});
        saveFormFactors(F, (dir / "sum.hff").string());
        CHECK_THROWS_WITH_AS(loadFormFactors((dir / "sum.hff").string()), doctest::Contains("row 0 of F sums to 1.4"),
                             Error);
    }
}

TEST_CASE("A damaged .mtx file fails with the line") {
    const auto dir = tempDir("mtx-bad");
    const std::string head = "%%MatrixMarket matrix coordinate real general\n3 3 2\n";
    CHECK_THROWS_WITH_AS(loadFormFactors(writeFile(dir / "a.mtx", head + "1 2 0.5\n4 1 0.1\n")),
                         doctest::Contains("a.mtx:4: entry (4, 1) is outside 1..3"), Error);
    CHECK_THROWS_WITH_AS(loadFormFactors(writeFile(dir / "b.mtx", head + "1 2 0.5\n")),
                         doctest::Contains("truncated: 1 of 2 entries"), Error);
    CHECK_THROWS_WITH_AS(loadFormFactors(writeFile(dir / "c.mtx", head + "1 2 -0.5\n2 1 .1\n")),
                         doctest::Contains("c.mtx:3: F value '-0.5' is negative"), Error);
    CHECK_THROWS_WITH_AS(loadFormFactors(writeFile(dir / "d.mtx", "%%MatrixMarket matrix array real general\n")),
                         doctest::Contains("unsupported Matrix Market type"), Error);
    CHECK_THROWS_WITH_AS(loadFormFactors(writeFile(dir / "e.mtx", head + "1 2 0.5\n1 2 0.1\n")),
                         doctest::Contains("duplicate entry (1, 2)"), Error);
}

TEST_CASE("F computed for another scene is refused") {
    const FormFactors F = sampleF();
    CHECK_NOTHROW(checkFormFactorsMatch(F, F.sceneHash, 4, "F.hff"));
    CHECK_THROWS_WITH_AS(checkFormFactorsMatch(F, F.sceneHash ^ 1, 4, "F.hff"),
                         doctest::Contains("F.hff: F was computed for another scene"), Error);
    CHECK_THROWS_WITH_AS(checkFormFactorsMatch(F, F.sceneHash, 5, "F.hff"),
                         doctest::Contains("F has 4 patches but the scene has 5"), Error);
}

TEST_CASE("The scene hash changes with geometry and mirrors, not with emission or diffuse reflectance") {
    Scene s = unitCube();
    const std::uint64_t h = s.geometryHash();
    s.patches[0].emission = Rgb(5, 5, 5);
    s.patches[1].rho = Rgb(0.1, 0.2, 0.3);
    CHECK(s.geometryHash() == h);
    s.patches[2].specular = 0.5;
    CHECK(s.geometryHash() != h);
    s.patches[2].specular = 0.0;
    s.vertices[0].x() += 1e-9;
    CHECK(s.geometryHash() != h);
}

TEST_CASE("The scene content hash sees the emission and reflectance and materials and subdivision that the F hash leaves out") {
    // MPI ranks agree on it (issue 35 #16: a rank with another Kd gave B up to 87 % off, silently).
    const Scene box = bundledScene("cornell_box.obj");
    const std::uint64_t h = box.contentHash();
    CHECK(Scene(box).contentHash() == h);
    Scene other = box;
    other.patches[0].emission = Rgb(5, 5, 5);
    CHECK(other.geometryHash() == box.geometryHash());
    CHECK(other.contentHash() != h);
    other = box;
    other.patches[1].rho = Rgb(0.1, 0.2, 0.3);
    CHECK(other.geometryHash() == box.geometryHash());
    CHECK(other.contentHash() != h);
    other = box;
    other.materials[0].rho = Rgb(0.1, 0.2, 0.3);  // as read from the MTL, for a faithful rewrite
    CHECK(other.contentHash() != h);
    other = box;
    other.vertices[other.corners[0]].x() += 1e-9;
    CHECK(other.contentHash() != h);
    CHECK(subdivide(box, 100.0).contentHash() != subdivide(box, 90.0).contentHash());
    CHECK(subdivide(box, 100.0).contentHash() == subdivide(box, 100.0).contentHash());
}

TEST_CASE("An uncommitted atomic write leaves the target untouched and no temporary file") {
    const auto dir = tempDir("atomic");
    const std::string target = writeFile(dir / "keep.txt", "original");
    {
        AtomicFile file(target, false);
        file.stream() << "half-written";
    }  // destroyed without commit, as when an exception unwinds
    CHECK(readAll(target) == "original");
    int files = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
    CHECK(files == 1);
    CHECK_THROWS_WITH_AS(AtomicFile((dir / "missing" / "x.hff").string()), doctest::Contains("cannot write"), Error);
}

TEST_CASE("A sharded F reads back as the one F it was split from, and a damaged shard set is refused") {
    const auto dir = tempDir("shards");
    const FormFactors F = sampleF();
    const std::string path = (dir / "F.hff").string();
    for (std::size_t count : {1, 2, 3, 5}) {
        CAPTURE(count);
        saveShardedFormFactors(F, path, count);
        CHECK(isShardManifest(path));
        const ShardManifest m = readShardManifest(path);
        REQUIRE(m.shards.size() == count);
        CHECK(m.patches == 4);
        CHECK(m.nonZeros == F.nonZeros());
        std::uint64_t rows = 0;
        for (const FormFactorShard& s : m.shards) rows += s.rows;
        CHECK(rows == F.computedRows());
        const FormFactors G = loadFormFactors(path);  // the manifest, merged
        requireSame(F, G);
        CHECK(G.provenance == F.provenance);
        CHECK(G.parameters == F.parameters);
        // Every shard is a valid F file on its own, holding its rows only.
        std::size_t held = 0;
        for (const FormFactorShard& s : m.shards) held += loadFormFactors(shardPath(path, s)).computedRows();
        CHECK(held == F.computedRows());
    }
    // A subset of shards: their rows only, the others not computed.
    saveShardedFormFactors(F, path, 2);
    const ShardManifest m = readShardManifest(path);
    const FormFactors first = loadShards(path, m, {0});
    CHECK(first.computedRows() == m.shards[0].rows);
    CHECK(first.rowComputed(0));
    CHECK_FALSE(first.rowComputed(3));

    const std::string shard1 = shardPath(path, m.shards[1]);
    const std::string manifestText = readAll(path);
    SUBCASE("a missing shard names the file") {
        std::filesystem::remove(shard1);
        CHECK_THROWS_WITH_AS(loadFormFactors(path), doctest::Contains((m.shards[1].file + ": cannot open").c_str()), Error);
    }
    SUBCASE("a shard of another run is refused by its checksum") {
        FormFactors other = sampleF();
        other.values()[other.rowBegin(3)] = 0.0625f;
        const std::string otherPath = (dir / "other.hff").string();
        saveShardedFormFactors(other, otherPath, 2);
        std::filesystem::copy_file(shardPath(otherPath, readShardManifest(otherPath).shards[1]), shard1,
                                   std::filesystem::copy_options::overwrite_existing);
        CHECK_THROWS_WITH_AS(loadFormFactors(path), doctest::Contains("does not match its manifest"), Error);
    }
    SUBCASE("a row in two shards") {
        std::string text = manifestText;
        const std::size_t first = text.find("\nshard ") + 1;
        text += text.substr(first, text.find('\n', first) + 1 - first);  // shard 0 listed twice
        // The duplicate makes the nonzero total wrong first; fix the total to reach the row check.
        const std::size_t nz = text.find("nonzeros ");
        const std::size_t eol = text.find('\n', nz);
        text.replace(nz, eol - nz, "nonzeros " + std::to_string(F.nonZeros() + m.shards[0].nonZeros));
        std::ofstream(path, std::ios::binary) << text;
        CHECK_THROWS_WITH_AS(loadFormFactors(path), doctest::Contains("is in two shards"), Error);
    }
    // The manifest with one piece of text replaced: refused with `expected` in the message.
    auto refusedWith = [&](const std::string& from, const std::string& to, const char* expected) {
        std::string text = manifestText;
        REQUIRE(text.find(from) != std::string::npos);
        text.replace(text.find(from), from.size(), to);
        std::ofstream(path, std::ios::binary) << text;
        CHECK_THROWS_WITH_AS(loadFormFactors(path), doctest::Contains(expected), Error);
    };
    SUBCASE("a damaged manifest names its line") { refusedWith("patches 4", "patches x", "F.hff:2:"); }
    SUBCASE("a manifest whose shard totals disagree") {
        refusedWith("nonzeros " + std::to_string(F.nonZeros()), "nonzeros 9", "the manifest announces");
    }
    SUBCASE("an impossible patch count is refused before anything of its size is allocated") {
        refusedWith("patches 4", "patches 9000000000000", "patch count '9000000000000' is out of range");
    }
    SUBCASE("a shard named outside the manifest's folder") {
        refusedWith(m.shards[0].file, "../" + m.shards[0].file, "is not a file name beside the manifest");
    }
}

TEST_CASE("Replacing a sharded F removes its old shards only once the new F is in place, and never another manifest's") {
    const auto dir = tempDir("shard-replace");
    const FormFactors F = sampleF();
    const std::string path = (dir / "F.hff").string();
    auto shardFiles = [&] {
        std::vector<std::string> names;
        for (const auto& entry : std::filesystem::directory_iterator(dir))
            if (entry.path().filename().string().find(".shard-") != std::string::npos)
                names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    };
    saveShardedFormFactors(F, path, 3);
    const ShardManifest three = readShardManifest(path);
    CHECK(shardFiles().size() == 3);
    // A copy of the manifest under another name, rewritten: the files it listed are F's, not its own.
    const std::string copy = (dir / "copy.hff").string();
    std::filesystem::copy_file(path, copy);
    saveShardedFormFactors(F, copy, 1);
    CHECK(shardFiles().size() == 4);
    requireSame(F, loadFormFactors(path));
    // F rewritten with another shard count: a new set, the old one removed once the manifest is in place.
    saveShardedFormFactors(F, path, 2);
    const ShardManifest two = readShardManifest(path);
    std::vector<std::string> expected = {readShardManifest(copy).shards[0].file, two.shards[0].file, two.shards[1].file};
    std::sort(expected.begin(), expected.end());
    CHECK(shardFiles() == expected);
    for (const FormFactorShard& s : three.shards) CHECK(std::find(expected.begin(), expected.end(), s.file) == expected.end());
    requireSame(F, loadFormFactors(path));
    requireSame(F, loadFormFactors(copy));
    // One F file in place of the manifest: its shards go, the copy's stay.
    saveFormFactors(F, path);
    CHECK_FALSE(isShardManifest(path));
    CHECK(shardFiles() == std::vector<std::string>{readShardManifest(copy).shards[0].file});
    requireSame(F, loadFormFactors(path));
}

TEST_CASE("Writing an F again removes a shard an interrupted sharded write left beside it, and nothing else") {
    const auto dir = tempDir("shard-orphans");
    const FormFactors F = sampleF();
    const std::string path = (dir / "F.hff").string();
    // Another manifest of the same stem in the folder (written through the library: only an .hff
    // path reads as a manifest): its shard is named F.shard-... too.
    const std::string sibling = (dir / "F.mtx").string();
    saveShardedFormFactors(F, sibling, 1);
    const std::string siblingShard = shardPath(sibling, readShardManifest(sibling).shards[0]);
    saveShardedFormFactors(F, path, 2);
    // What a 3-rank write leaves when Ctrl-C comes after one rank renamed its shard into place and
    // before rank 0 wrote the manifest: a complete shard that no manifest lists.
    auto leaveOrphan = [&](std::uint32_t setId) {
        const std::string orphan = (dir / shardFileName(path, 1, 3, setId)).string();
        std::filesystem::copy_file(shardPath(path, readShardManifest(path).shards[0]), orphan);
        return orphan;
    };
    const std::string orphan = leaveOrphan(0x0badc0de);
    // Names close to a shard's that are not one of F's: kept.
    const std::vector<std::string> strangers = {
        "F.shard-1-of-3.0badc0d.hff",      "F.shard-1-of-3.0BADC0DE.hff", "F.shard-3-of-3.0badc0de.hff",
        "F.shard-01-of-3.0badc0de.hff",    "F.shard-1-of-3.0badc0de.hff.bak", "F.shard-notes.txt",
        "G.shard-1-of-3.0badc0de.hff",     "xF.shard-1-of-3.0badc0de.hff"};
    for (const std::string& name : strangers) writeFile(dir / name, "not a shard of F\n");
    auto strangersKept = [&] {
        for (const std::string& name : strangers) {
            CAPTURE(name);
            CHECK(std::filesystem::exists(dir / name));
        }
    };

    saveShardedFormFactors(F, path, 2);
    CHECK_FALSE(std::filesystem::exists(orphan));
    for (const FormFactorShard& s : readShardManifest(path).shards) CHECK(std::filesystem::exists(shardPath(path, s)));
    requireSame(F, loadFormFactors(path));
    CHECK(std::filesystem::exists(siblingShard));
    requireSame(F, loadShardedFormFactors(sibling));
    strangersKept();

    // An F file written in place of the manifest sweeps them too.
    const std::string second = leaveOrphan(0x0badc0df);
    saveFormFactors(F, path);
    CHECK_FALSE(std::filesystem::exists(second));
    requireSame(F, loadFormFactors(path));
    CHECK(std::filesystem::exists(siblingShard));
    requireSame(F, loadShardedFormFactors(sibling));
    strangersKept();
}

TEST_CASE("Odd but valid parameter keys and values round-trip through .hff, .mtx and a shard manifest") {
    // Issue 35 #8: what Hemirad writes it reads back, key and value as they were.
    const auto dir = tempDir("ff-odd-parameters");
    FormFactors F = sampleF();
    F.parameters = {{"note", "spaces inside, 'quotes', \"double\", # hash, % percent, key=value, a\\b, café 光"},
                    {"weird.key-name:1/2", "x"},
                    {"%starts_with_percent", "v"},
                    {"empty", ""},
                    {"trailing_backslash_key\\", "y"},
                    {"ключ", "значение"}};
    for (const char* name : {"F.hff", "F.mtx", "S.hff"}) {
        CAPTURE(name);
        const std::string path = (dir / name).string();
        if (std::string(name) == "S.hff") saveShardedFormFactors(F, path, 2);
        else saveFormFactors(F, path);
        const FormFactors G = loadFormFactors(path);
        requireSame(F, G);
        CHECK(G.parameters == F.parameters);
        CHECK(G.provenance == F.provenance);
    }
}

TEST_CASE("A parameter that a file could not hold is refused on write, naming it, and no file is left") {
    // Issue 35 #8: a newline in a value wrote a file that read back as 'corrupt parameter text'; a key
    // 'a=b' read back as 'a'. Refused before anything is written, in every format.
    const auto dir = tempDir("ff-bad-parameters");
    const struct {
        std::string key, value, message;
    } refused[] = {
        {"note", "two\nlines", "parameter 'note': value 'two\\x0alines' holds a control character"},
        {"note", "carriage\rreturn", "parameter 'note': value 'carriage\\x0dreturn' holds a control character"},
        {"note", "tab\there", "parameter 'note': value 'tab\\x09here' holds a control character"},
        {"a=b", "c", "parameter key 'a=b' holds '='"},
        {"a b", "c", "parameter key 'a b' holds a space"},
        {"", "c", "parameter key '' is empty"},
        {"line\nbreak", "c", "parameter key 'line\\x0abreak' holds a control character"},
        {"note", " leading", "parameter 'note': value ' leading' starts or ends with a space"},
        {"note", "trailing ", "parameter 'note': value 'trailing ' starts or ends with a space"},
        {"note", "two  spaces", "parameter 'note': value 'two  spaces' holds two spaces in a row"},
        {"note", "ends in a backslash\\", "parameter 'note': value 'ends in a backslash\\' ends with a backslash"},
    };
    for (const auto& r : refused) {
        CAPTURE(r.message);
        FormFactors F = sampleF();
        F.parameters[r.key] = r.value;
        for (const char* name : {"F.hff", "F.mtx", "S.hff"}) {
            CAPTURE(name);
            const std::string path = (dir / name).string();
            if (std::string(name) == "S.hff")
                CHECK_THROWS_WITH_AS(saveShardedFormFactors(F, path, 2), doctest::Contains(r.message.c_str()), Error);
            else
                CHECK_THROWS_WITH_AS(saveFormFactors(F, path), doctest::Contains(r.message.c_str()), Error);
        }
        CHECK(std::filesystem::is_empty(dir));
    }
    // The provenance is stored as parameters too: a method name is held to the same rules.
    FormFactors F = sampleF();
    F.provenance.method = "hemi\nsphere";
    CHECK_THROWS_WITH_AS(saveFormFactors(F, (dir / "F.hff").string()),
                         doctest::Contains("F.hff: parameter 'method': value 'hemi\\x0asphere'"), Error);
}
