// The file browser behind File > Open, Save, Import and Export: a directory listing filtered by
// extension, navigation, recent folders and typed paths. No ImGui here: the panel draws it, tests drive it.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace hemirad::ui {

class FileBrowser {
public:
    struct Entry {
        std::string name;        ///< file or directory name; ".." for the parent
        bool directory = false;
        std::uintmax_t size = 0; ///< bytes (files)
    };

    /// Starts browsing for `purpose` ("Open OBJ", ...): files ending in one of `extensions` (".obj";
    /// case-insensitive; empty: all files) are listed, in the folder of `initial` (else the working
    /// directory), with `initial` as the typed path. `mustExist`: Open and Import (not Save, Export).
    void start(const std::string& purpose, std::vector<std::string> extensions, const std::string& initial, bool mustExist);

    const std::string& purpose() const { return m_purpose; }
    const std::vector<std::string>& extensions() const { return m_extensions; }
    /// The folder shown (absolute).
    const std::string& directory() const { return m_directory; }
    /// Its listing: "..", folders, then matching files, each group by name; hidden entries left out.
    const std::vector<Entry>& entries() const { return m_entries; }
    /// Why the folder could not be listed (empty when it could).
    const std::string& error() const { return m_error; }

    /// Shows another folder (absolute, or relative to the one shown). Returns false (error() says
    /// why) when it cannot be listed; the folder shown stays.
    bool changeDirectory(const std::string& path);
    /// A click on an entry: a folder is entered, a file becomes the typed path (its name).
    void pick(const Entry& entry);
    /// A click on an entry of the listing shown, `doubleClick` when it completes a double-click: a
    /// single click picks; a double-click on a file gives its absolute path (as confirm). The second
    /// click of a double-click is ignored unless its first fell on the same entry of the same listing:
    /// a double-click on a folder enters it once and must not also open (or enter) what lands under
    /// the pointer in the new listing.
    std::optional<std::string> click(const Entry& entry, bool doubleClick);
    /// Enter or OK on the typed path: a folder is entered (none returned); a file gives its absolute
    /// path (relative paths are relative to the folder shown). A missing file where one must exist,
    /// or an empty path, sets error() and gives none.
    std::optional<std::string> confirm(const std::string& typed);

    /// The path being typed (the panel's text field).
    std::string typed;
    /// Folders of recently used files, newest first, without duplicates.
    static std::vector<std::string> recentFolders(const std::deque<std::string>& recentFiles);

private:
    void list();
    bool matches(const std::string& name) const;

    std::string m_purpose, m_directory, m_error;
    std::vector<std::string> m_extensions;
    std::vector<Entry> m_entries;
    bool m_mustExist = false;
    std::uint64_t m_listing = 0;  ///< bumped by every listing made
    std::uint64_t m_clickListing = 0;  ///< the listing the last single click fell on
    std::string m_clickName;           ///< and its entry
};

}  // namespace hemirad::ui
