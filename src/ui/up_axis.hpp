// The scene's up axis in hemirad-gui (y or z): stated by the OBJ ('# hemirad up z'), chosen in the
// Scene panel and remembered per scene file, else guessed from the bounding box. The orbit camera
// frames and orbits about it.
#pragma once

#include "engine/scene.hpp"

#include <map>
#include <string>

namespace hemirad::ui {

/// Where a scene's up axis comes from, as the Scene panel says.
enum class UpAxisSource { Stated, Remembered, Guessed };

/// The up axis the bounding box suggests: z (2) when the scene is much flatter along z than along y
/// (less than half: a Z-up site or floor plan), else y (1), the OBJ convention.
int guessUpAxis(const Scene& scene);
/// The scene's stated up axis (Scene::up), else the guess: 1 (y) or 2 (z).
int upAxisOf(const Scene& scene);
/// "y" or "z".
const char* upAxisName(int axis);
/// "stated in the OBJ", "remembered for this file", "guessed from the bounding box".
const char* upAxisSourceText(UpAxisSource source);

/// The up axes chosen per scene file (absolute paths), kept in a text file of "y|z PATH" lines
/// (hemirad-gui: $XDG_CONFIG_HOME/hemirad/up-axes). An empty file path keeps them in memory only;
/// a file that cannot be read or written is a convenience lost, never an error.
class UpAxisMemory {
public:
    explicit UpAxisMemory(std::string file = {});
    /// The axis chosen for `scenePath`, 0 when none was.
    int recall(const std::string& scenePath) const;
    /// Remembers `axis` (1 or 2) for `scenePath` and writes the file.
    void remember(const std::string& scenePath, int axis);

private:
    std::string m_file;
    std::map<std::string, int> m_axes;
};

}  // namespace hemirad::ui
