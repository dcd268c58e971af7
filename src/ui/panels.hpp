// hemirad-gui's ImGui panels: they present AppState and emit actions, nothing else.
#pragma once

#include "ui/app_state.hpp"
#include "ui/file_browser.hpp"
#include "ui/inspector.hpp"
#include "ui/material_fields.hpp"
#include "ui/orbit_camera.hpp"
#include "ui/sun_sky_panel.hpp"
#include "ui/thermal_panel.hpp"

#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>

namespace hemirad::ui {

/// Requests the event loop carries out (they need the window or happen between frames).
struct LoopRequests {
    bool quit = false;             ///< confirmed: leave the loop
    std::string exportImage;       ///< write the view (without the UI) to this PNG after drawing
};

class Panels {
public:
    explicit Panels(std::string recentFilesPath);
    /// Draws the menu bar and windows; `viewExposure` is the exposure the view is using, `hovered`
    /// the patch under the cursor (the status bar reads it out).
    void draw(AppState& app, OrbitCamera& camera, Inspector& inspector, double viewExposure, LoopRequests& requests,
              std::optional<PatchId> hovered = std::nullopt);
    /// The status bar's text: the hovered (else selected) patch's id, object, B, H, E, rho, s and F_ij
    /// from the selected patch, T and q after a thermal run, the view's exposure, F's memory.
    static std::string statusText(const AppState& app, std::optional<PatchId> hovered, double viewExposure);
    /// The status bar's text in the last frame (scripted runs print it).
    const std::string& status() const { return m_status; }
    /// Asks before an action that would drop unsaved edits (open, quit); runs it at once if none.
    void guarded(AppState& app, const std::string& what, std::function<void()> action);
    /// Opens a file (recent files updated); asks first when edits are unsaved.
    void open(AppState& app, OrbitCamera& camera, const std::string& path);
    const std::deque<std::string>& recentFiles() const { return m_recent; }
    /// Opens the file browser for `purpose` ("Open OBJ", "Save scene", "Import F", "Export F",
    /// "Export PNG", "Export PLY", "Export object table", "Thermal properties", "Boundary conditions",
    /// "Export exchange table") at `initial`; the help window closes.
    void browse(const std::string& purpose, const std::string& initial);
    /// File > Save (Ctrl+S): over the scene's .obj, or through the browser when it has none.
    void save(AppState& app);
    /// View > Object table: shows the table's window.
    void showObjectTable() { m_showObjects = true; }
    /// The object table as drawn in the last frame: the headings, then a row per object, each cell's
    /// text (empty when the window was not drawn); scripted runs print it.
    const std::vector<std::vector<std::string>>& objectTable() const { return m_objectTable; }
    /// The legend's tick labels as drawn in the last frame, bottom to top (empty without a legend).
    const std::vector<std::string>& legendTicks() const { return m_legendTicks; }
    /// View > Thermal exchange table: shows its window (once there is a thermal result).
    void showThermalExchange() { m_thermal.showExchange = true; }
    /// The thermal section and exchange table as drawn in the last frame (scripted runs print them).
    const ThermalPanel& thermal() const { return m_thermal; }
    /// The Sky and sun section as drawn in the last frame (scripted runs print it).
    const SunSkyPanel& sunSky() const { return m_sunSky; }
    /// The legend's title and unit as drawn in the last frame (empty when it was not drawn).
    const std::pair<std::string, std::string>& legend() const { return m_legend; }
    /// Help > Keyboard and mouse (F1): shows or hides the help window.
    void toggleHelp() { m_showHelp = !m_showHelp; }
    /// Esc: closes the help window; returns whether it was open.
    bool closeHelp() { return std::exchange(m_showHelp, false); }

    struct Rect {
        float x = 0, y = 0, width = 0, height = 0;
    };
    /// Where each panel drawn in the last frame was (window pixels), by name: scripted runs print
    /// them and a test checks they stay inside the window and apart.
    const std::map<std::string, Rect>& panelRects() const { return m_panelRects; }
    /// Where some controls were in the last frame, for scripted clicks: "CancelButton" (the menu
    /// bar's, while a job runs), "PipelineCancel", "FilesRow0".."FilesRow2" (the browser's listing).
    const std::map<std::string, Rect>& itemRects() const { return m_itemRects; }
    /// The default layout for a window of this size.
    struct Layout {
        Rect scene, pipeline, selection, log, legend, status;
    };
    static Layout layout(float width, float height);

private:
    bool beginPanel(const char* name, const Rect& rect, bool relayout);
    void menuBar(AppState& app, OrbitCamera& camera, LoopRequests& requests);
    void scenePanel(AppState& app, OrbitCamera& camera);
    void materialPanel(AppState& app);
    void selectionPanel(AppState& app, Inspector& inspector, double viewExposure);
    void pipelinePanel(AppState& app);
    /// The pipeline's first step: mesh the scene or the selected objects to a maximum edge length.
    void meshingSection(AppState& app);
    void logPanel(AppState& app);
    void statusBar(AppState& app, const Rect& rect, std::optional<PatchId> hovered, double viewExposure);
    /// The false colour's settings and legend (legend_panel.cpp).
    void legendPanel(AppState& app);
    /// The F-row layer's scale: F from the selected patch, log over 4 decades (legend_panel.cpp).
    void rowLegendPanel(AppState& app);
    /// A colour bar of `colourAt(t)` (t 0 at the bottom .. 1 at the top) labelled with round values
    /// of `range` (legendTicks), then the scale's note.
    void colourBar(const FalseColourRange& range, const std::function<std::array<std::uint8_t, 3>(double)>& colourAt,
                   const std::string& note);
    void objectsPanel(AppState& app);
    void helpPanel();
    void modals(AppState& app, OrbitCamera& camera, LoopRequests& requests);
    void remember(const std::string& path);

    std::string m_recentPath;
    std::deque<std::string> m_recent;
    // The file browser (no native file dialogs) and the path being typed in it.
    FileBrowser m_browser;
    char m_pathBuffer[1024] = {};
    bool m_openPathPrompt = false;
    bool m_focusPath = false;  ///< put the keyboard in the path field (on opening, after navigating)
    // Confirmation of an action that drops unsaved edits.
    std::string m_confirmWhat;
    std::function<void()> m_confirmAction;
    bool m_openConfirm = false;
    MaterialFields m_material;  ///< the material editor's values (applied on release)
    bool m_showInspector = true;
    float m_layoutWidth = 0, m_layoutHeight = 0;  ///< the window size the layout was applied for
    bool m_selectionHidden = true;                 ///< the Selection panel was not drawn last frame
    bool m_legendHidden = true;                    ///< the Legend panel was not drawn last frame
    std::vector<std::string> m_legendTicks;        ///< the legend's tick labels as drawn last
    // The F-row legend's row: for which patch and F, and its largest factor.
    std::optional<PatchId> m_rowPatch;
    const FormFactors* m_rowF = nullptr;
    std::uint64_t m_rowRevision = 0;
    double m_rowMax = 0.0;
    bool m_showObjects = false;                    ///< View > Object table
    std::vector<std::vector<std::string>> m_objectTable;  ///< the object table as drawn last
    bool m_showHelp = false;                       ///< Help > Keyboard and mouse (F1)
    // Meshing section: the edge length typed, whole scene or selected objects, for which scene.
    double m_meshEdge = 0.0;
    bool m_meshSelected = false;
    std::uint64_t m_meshSceneId = 0;  ///< the scene the suggested edge length was made for
    std::vector<double> m_meshEdgesSeen;  ///< the mesh's edge lengths the fields were last set from
    float m_pipelineEnd = 0.0f;  ///< the Pipeline panel's tallest content so far (it never shrinks)
    ThermalPanel m_thermal;
    SunSkyPanel m_sunSky;                        ///< the Scene panel's Thermal section, the exchange table
    std::pair<std::string, std::string> m_legend;  ///< the legend's title and unit as drawn last
    std::map<std::string, Rect> m_panelRects, m_itemRects;
    std::string m_status;
};

}  // namespace hemirad::ui
