// Directory listing, navigation and typed paths for hemirad-gui's file browser.
#include "ui/file_browser.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

namespace hemirad::ui {
namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

}  // namespace

void FileBrowser::start(const std::string& purpose, std::vector<std::string> extensions, const std::string& initial,
                        bool mustExist) {
    m_purpose = purpose;
    m_extensions.clear();
    for (const std::string& e : extensions) m_extensions.push_back(lower(e));
    m_mustExist = mustExist;
    m_error.clear();
    std::error_code ec;
    fs::path folder = initial.empty() ? fs::path() : fs::path(initial).parent_path();
    if (!initial.empty() && fs::is_directory(initial, ec)) folder = initial;
    m_directory = fs::current_path(ec).string();
    if (folder.empty() || !changeDirectory(folder.string())) changeDirectory(m_directory);
    m_error.clear();
    typed = initial.empty() || fs::is_directory(initial, ec) ? std::string() : fs::path(initial).filename().string();
}

bool FileBrowser::matches(const std::string& name) const {
    if (m_extensions.empty()) return true;
    const std::string n = lower(name);
    return std::any_of(m_extensions.begin(), m_extensions.end(), [&](const std::string& e) {
        return n.size() > e.size() && n.compare(n.size() - e.size(), e.size(), e) == 0;
    });
}

bool FileBrowser::changeDirectory(const std::string& path) {
    std::error_code ec;
    const fs::path target = fs::weakly_canonical(fs::path(m_directory) / path, ec);
    if (ec || !fs::is_directory(target, ec)) {
        m_error = "not a folder: " + (fs::path(m_directory) / path).lexically_normal().string();
        return false;
    }
    fs::directory_iterator probe(target, ec);
    if (ec) {
        m_error = "cannot list " + target.string() + ": " + ec.message();
        return false;
    }
    m_directory = target.string();
    m_error.clear();
    list();
    return true;
}

void FileBrowser::list() {
    ++m_listing;
    std::vector<Entry> folders, files;
    std::error_code ec;
    for (fs::directory_iterator it(m_directory, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.empty() || name[0] == '.') continue;
        std::error_code statError;
        if (it->is_directory(statError)) {
            folders.push_back({name, true, 0});
        } else if (matches(name)) {
            const std::uintmax_t size = it->file_size(statError);
            files.push_back({name, false, statError ? 0 : size});
        }
    }
    if (ec) m_error = "cannot list " + m_directory + ": " + ec.message();
    const auto byName = [](const Entry& a, const Entry& b) { return a.name < b.name; };
    std::sort(folders.begin(), folders.end(), byName);
    std::sort(files.begin(), files.end(), byName);
    m_entries.clear();
    if (fs::path(m_directory).has_relative_path()) m_entries.push_back({"..", true, 0});
    m_entries.insert(m_entries.end(), folders.begin(), folders.end());
    m_entries.insert(m_entries.end(), files.begin(), files.end());
}

void FileBrowser::pick(const Entry& entry) {
    if (entry.directory) {
        changeDirectory(entry.name);
        typed.clear();
    } else {
        typed = entry.name;
        m_error.clear();
    }
}

std::optional<std::string> FileBrowser::click(const Entry& entry, bool doubleClick) {
    if (doubleClick) {
        const bool sameEntry = m_clickListing == m_listing && m_clickName == entry.name;
        m_clickName.clear();
        if (!sameEntry) return std::nullopt;
        if (!entry.directory) return confirm(entry.name);
    }
    m_clickListing = m_listing;
    m_clickName = entry.name;
    pick(entry);
    return std::nullopt;
}

std::optional<std::string> FileBrowser::confirm(const std::string& text) {
    typed = text;
    if (text.empty()) {
        m_error = "type a file name or pick one";
        return std::nullopt;
    }
    const fs::path path = fs::path(m_directory) / text;  // an absolute text replaces the folder
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        if (changeDirectory(path.string())) typed.clear();
        return std::nullopt;
    }
    if (m_mustExist && !fs::exists(path, ec)) {
        m_error = "no such file: " + path.lexically_normal().string();
        return std::nullopt;
    }
    m_error.clear();
    return path.lexically_normal().string();
}

std::vector<std::string> FileBrowser::recentFolders(const std::deque<std::string>& recentFiles) {
    std::vector<std::string> folders;
    for (const std::string& file : recentFiles) {
        const std::string folder = fs::path(file).parent_path().string();
        if (!folder.empty() && std::find(folders.begin(), folders.end(), folder) == folders.end()) folders.push_back(folder);
    }
    return folders;
}

}  // namespace hemirad::ui
