// Up axis: the bounding-box guess and the per-file memory of the Scene panel's choice.
#include "ui/up_axis.hpp"

#include "engine/atomic_file.hpp"

#include <filesystem>
#include <fstream>

namespace hemirad::ui {

int guessUpAxis(const Scene& scene) {
    if (scene.size() == 0) return 1;
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const Vec3 size = hi - lo;
    // Z-up data (sites, CAD floor plans) spread in x and y and are low in z; a Y-up scene of the
    // same kind is low in y, and a room or a box is about as deep as it is high: y.
    return size.z() < 0.5 * size.y() ? 2 : 1;
}

int upAxisOf(const Scene& scene) { return scene.up == 1 || scene.up == 2 ? scene.up : guessUpAxis(scene); }

const char* upAxisName(int axis) { return axis == 2 ? "z" : "y"; }

const char* upAxisSourceText(UpAxisSource source) {
    switch (source) {
        case UpAxisSource::Stated: return "stated in the OBJ";
        case UpAxisSource::Remembered: return "remembered for this file";
        case UpAxisSource::Guessed: return "guessed from the bounding box";
    }
    return "";
}

UpAxisMemory::UpAxisMemory(std::string file) : m_file(std::move(file)) {
    if (m_file.empty()) return;
    std::ifstream in(m_file);
    std::string line;
    while (std::getline(in, line))
        if (line.size() > 2 && (line[0] == 'y' || line[0] == 'z') && line[1] == ' ') m_axes[line.substr(2)] = line[0] == 'z' ? 2 : 1;
}

int UpAxisMemory::recall(const std::string& scenePath) const {
    std::error_code ec;
    const auto it = m_axes.find(std::filesystem::absolute(scenePath, ec).lexically_normal().string());
    return it == m_axes.end() ? 0 : it->second;
}

void UpAxisMemory::remember(const std::string& scenePath, int axis) {
    std::error_code ec;
    m_axes[std::filesystem::absolute(scenePath, ec).lexically_normal().string()] = axis == 2 ? 2 : 1;
    if (m_file.empty()) return;
    try {
        std::filesystem::create_directories(std::filesystem::path(m_file).parent_path());
        AtomicFile file(m_file, false);
        for (const auto& [path, a] : m_axes) file.stream() << upAxisName(a) << ' ' << path << '\n';
        file.commit();
    } catch (const std::exception&) {
        // Remembering is a convenience: a read-only home must not stop the program.
    }
}

}  // namespace hemirad::ui
