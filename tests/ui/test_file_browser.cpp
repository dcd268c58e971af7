// hemirad-gui's file browser without a window: listing filtered by extension, navigation, typed paths.
#include "support.hpp"

#include "ui/file_browser.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

using namespace hemirad::test;
using hemirad::ui::FileBrowser;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> names(const FileBrowser& b) {
    std::vector<std::string> out;
    for (const auto& e : b.entries()) out.push_back(e.name + (e.directory ? "/" : ""));
    return out;
}

}  // namespace

TEST_CASE("The file browser lists folders, then the files of the purpose's extensions, and navigates by click and by typed path") {
    const fs::path dir = tempDir("file-browser");
    fs::create_directories(dir / "scenes" / "more");
    fs::create_directories(dir / ".hidden");
    for (const char* name : {"scenes/b.obj", "scenes/A.OBJ", "scenes/a.mtl", "scenes/F.hff", "scenes/.secret.obj", "scenes/more/c.obj"})
        std::ofstream(dir / name) << "# x\n";

    FileBrowser b;
    b.start("Open OBJ", {".obj"}, (dir / "scenes" / "b.obj").string(), true);
    CHECK(b.directory() == fs::canonical(dir / "scenes").string());
    CHECK(b.typed == "b.obj");
    CHECK(names(b) == std::vector<std::string>{"../", "more/", "A.OBJ", "b.obj"});  // case-insensitive filter, no hidden files
    // A click on a folder enters it, on a file types its name; ".." goes up.
    b.pick(b.entries()[1]);
    CHECK(b.directory() == fs::canonical(dir / "scenes" / "more").string());
    CHECK(names(b) == std::vector<std::string>{"../", "c.obj"});
    b.pick(b.entries()[1]);
    CHECK(b.typed == "c.obj");
    CHECK(b.confirm(b.typed) == (fs::canonical(dir / "scenes" / "more") / "c.obj").string());
    b.pick(b.entries()[0]);
    CHECK(b.directory() == fs::canonical(dir / "scenes").string());
    // Typed: a folder (relative or absolute) is entered and gives no file; a file gives its absolute path.
    CHECK_FALSE(b.confirm("more").has_value());
    CHECK(b.directory() == fs::canonical(dir / "scenes" / "more").string());
    CHECK_FALSE(b.confirm((dir / "scenes").string()).has_value());
    CHECK(b.directory() == fs::canonical(dir / "scenes").string());
    CHECK(b.confirm("more/c.obj") == (fs::canonical(dir / "scenes") / "more" / "c.obj").string());
    CHECK(b.confirm((dir / "scenes" / "b.obj").string()) == (dir / "scenes" / "b.obj").lexically_normal().string());
    // Open needs an existing file; Save does not.
    CHECK_FALSE(b.confirm("missing.obj").has_value());
    CHECK(b.error().find("no such file") != std::string::npos);
    CHECK_FALSE(b.confirm("").has_value());
    FileBrowser save;
    save.start("Save scene", {".obj"}, (dir / "scenes" / "new.obj").string(), false);
    CHECK(save.typed == "new.obj");
    CHECK(save.confirm(save.typed) == (fs::canonical(dir / "scenes") / "new.obj").string());
    // Import F lists F files only; a folder that cannot be listed is an error and the shown one stays.
    FileBrowser import;
    import.start("Import F", {".hff", ".mtx"}, (dir / "scenes" / "x.hff").string(), true);
    CHECK(names(import) == std::vector<std::string>{"../", "more/", "F.hff"});
    CHECK_FALSE(import.changeDirectory("nowhere"));
    CHECK(import.error().find("not a folder") != std::string::npos);
    CHECK(import.directory() == fs::canonical(dir / "scenes").string());
    // A start path in a missing folder falls back to the working directory.
    FileBrowser lost;
    lost.start("Open OBJ", {".obj"}, "/no/such/folder/x.obj", true);
    CHECK(lost.directory() == fs::current_path().string());
    // Recent folders: newest first, once each.
    CHECK(FileBrowser::recentFolders({"/a/x.obj", "/b/y.obj", "/a/z.obj"}) == std::vector<std::string>{"/a", "/b"});
}

TEST_CASE("The file browser's double-click on a folder enters it once, a double-click on a file opens it (issue 38 #1)") {
    const fs::path dir = tempDir("file-browser-double");
    fs::create_directories(dir / "sub" / "deeper");
    for (const char* name : {"sub/b.obj", "top.obj"}) std::ofstream(dir / name) << "# x\n";
    FileBrowser b;
    b.start("Open OBJ", {".obj"}, (dir / "top.obj").string(), true);
    REQUIRE(names(b) == std::vector<std::string>{"../", "sub/", "top.obj"});
    // Its first click enters sub; its second lands on the new listing's row 1 (deeper/, then b.obj
    // in row 2) and is ignored: neither entered nor opened.
    CHECK_FALSE(b.click(b.entries()[1], false));
    REQUIRE(names(b) == std::vector<std::string>{"../", "deeper/", "b.obj"});
    CHECK_FALSE(b.click(b.entries()[1], true));
    CHECK(b.directory() == fs::canonical(dir / "sub").string());
    CHECK_FALSE(b.click(b.entries()[2], true));
    CHECK(b.typed.empty());
    // A double-click on a file (both clicks on it) gives its path.
    CHECK_FALSE(b.click(b.entries()[2], false));
    CHECK(b.typed == "b.obj");
    const auto chosen = b.click(b.entries()[2], true);
    REQUIRE(chosen);
    CHECK(*chosen == (fs::canonical(dir / "sub") / "b.obj").string());
}
