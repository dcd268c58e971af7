// One GL context's hemicube machinery: scene buffers, the one-draw five-face pass, CPU/GPU reduction.
#pragma once

#include "engine/scene.hpp"
#include "gl/gl_objects.hpp"
#include "preprocess/hemicube/hemicube_geometry.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "preprocess/hemicube/hemicube_options.hpp"
#include "preprocess/row_accumulator.hpp"

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace hemirad {

/// Per-stage seconds and pixel counts of the hemicubes a renderer drew.
struct HemicubeStats {
    /// CPU seconds: issuing a pass's commands (render), synchronous read-backs (readback), waiting
    /// for a pass in flight (wait), summing into rows (reduce), handing rows over (collect), mirrors.
    double render = 0, readback = 0, wait = 0, reduce = 0, collect = 0, mirrors = 0;
    /// GPU seconds of the passes (timestamps): drawing, and reading back or reducing.
    double gpuDraw = 0, gpuFinish = 0;
    std::uint64_t hemicubes = 0, pixels = 0, missed = 0, backfaces = 0, portals = 0;
    double lostWeight = 0;    ///< sum over rows of the row fraction that saw nothing or a back face
    double cutoffWeight = 0;  ///< sum over rows of the fraction still travelling at the depth/weight limit
    double lostHandedOver = 0;  ///< lostWeight when the last row was handed over (not summed by +=)
    HemicubeStats& operator+=(const HemicubeStats& o) {
        render += o.render, readback += o.readback, wait += o.wait, reduce += o.reduce, collect += o.collect,
            mirrors += o.mirrors, gpuDraw += o.gpuDraw, gpuFinish += o.gpuFinish;
        hemicubes += o.hemicubes, pixels += o.pixels, missed += o.missed, backfaces += o.backfaces, portals += o.portals;
        lostWeight += o.lostWeight, cutoffWeight += o.cutoffWeight;
        return *this;
    }
};

class RayScene;
class HemicubeRowPool;

/// Mirror handling: portals (stencil, reflected views) or, with `rays`, the reference system's
/// hybrid: pixels that see a mirror continue as Embree rays. Chains stop after maxDepth
/// reflections or below minWeight.
struct MirrorLimits {
    std::uint32_t maxDepth = 8;
    double minWeight = 1e-4;
    const RayScene* rays = nullptr;
};

/// One hemicube of a batch: patch `patch` seen from `origin` (a point of it), its deposits times
/// `weight` (the point's share of the row; the weights of a row's points sum to 1).
struct HemicubeItem {
    PatchId patch;
    Vec3 origin;
    double weight;
};

/// Requires a current GL 4.5 context for its whole life (construction, use, destruction).
class HemicubeRenderer {
public:
    /// `layers`: hemicubes drawn per pass (the atlas is an array of that many layers); `inFlight`:
    /// passes that may be read back or reduced while the next ones draw. `exclusive`, for a driver
    /// whose contexts may not run commands at once (hemicubeSerializesContexts): held over each of
    /// this renderer's GL command sequences, from its construction to its destruction; the CPU
    /// reductions run outside it.
    HemicubeRenderer(const Scene& scene, const HemicubeGeometry& geometry, const HemicubeLayout& layout,
                     Reduction reduction, const MirrorLimits& mirrors = {}, std::uint32_t layers = 1,
                     std::uint32_t inFlight = 1, std::mutex* exclusive = nullptr);
    ~HemicubeRenderer();
    HemicubeRenderer(const HemicubeRenderer&) = delete;
    HemicubeRenderer& operator=(const HemicubeRenderer&) = delete;

    std::uint32_t layers() const { return m_layers; }
    /// Finished passes' rows go to `pool`'s threads (their rowDone) instead of computeBatch's
    /// rowDone; the pool must outlive the renderer's last drain() and be drained before it is
    /// destroyed. computeRow stays on the calling thread. Adds a slot, so that the one the pool
    /// sums is not the next one drawn into.
    void useRowPool(HemicubeRowPool* pool);

    /// Draws patch i's hemicube at its centroid and deposits each pixel's delta form factor on the
    /// patch it sees (weights in `row` relative to 1 = the whole row).
    void computeRow(PatchId i, RowAccumulator& row, HemicubeStats& stats) {
        computeRow(i, m_scene.patches[i].centroid, 1.0, row, stats);
    }
    /// The same from the point `origin` of patch i, its deposits times `weight`, at once (passes in
    /// flight stay so). Follows mirrors.
    void computeRow(PatchId i, const Vec3& origin, double weight, RowAccumulator& row, HemicubeStats& stats);

    /// Queues up to layers() hemicubes as one instanced pass whose reduction runs on while later
    /// passes draw; when all passes in flight are taken, the oldest is finished first. Mirrors are
    /// drawn as plain patches: only hemicubes that cannot see one belong here. A row's items must be
    /// consecutive and in one pass; after a row's last one is reduced, rowDone(patch) is called
    /// with its deposits in `row` (take them there).
    template <class RowDone>
    void computeBatch(const std::vector<HemicubeItem>& items, RowAccumulator& row, RowDone&& rowDone,
                      HemicubeStats& stats) {
        if (m_busy == m_inFlight) finishOldest(row, rowDone, stats);
        submit(items, stats);
    }
    /// Finishes every pass in flight (computeBatch's rows all handed over).
    template <class RowDone>
    void drain(RowAccumulator& row, RowDone&& rowDone, HemicubeStats& stats) {
        while (m_busy) finishOldest(row, rowDone, stats);
    }

private:
    /// Per-hemicube data of a pass (hemicube.vert's Hemicubes block, std430).
    struct Instance {
        Eigen::Matrix4f frameFromWorld;
        std::uint32_t skipCode = 0, pad[3] = {0, 0, 0};
    };
    /// One draw of the scene into the five faces. transform (world -> world) holds the product of
    /// the reflections of a portal chain; clipPlane keeps what lies in front of the last mirror.
    struct Pass {
        Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
        Eigen::Vector4d clipPlane = Eigen::Vector4d(0, 0, 0, 1);
        std::uint32_t skipCode = 0;
        bool mirrored = false;   ///< an odd number of reflections flips the winding
        bool planeTest = true;   ///< drop triangles behind the patch plane (direct pass only)
    };
    /// Where a pass's results land: a host-visible buffer, mapped for the renderer's life, that the
    /// GPU fills after the pass (CPU reduction: the atlas layers' ids; GPU reduction: per layer its
    /// header and the offset of its (patch, value) pairs, then the pairs), with the fence that says
    /// it is filled and timestamps around the draw. A CPU reduction that overlaps nothing reads
    /// into `host` instead, at once, without fence or timestamps (on llvmpipe each costs about as
    /// much as the read-back itself).
    struct Slot {
        gl::Buffer buffer;
        std::vector<std::uint32_t> host;
        const std::uint32_t* data = nullptr;
        GLsync fence = nullptr;
        GLuint queries[3] = {0, 0, 0};  ///< GL_TIMESTAMP: pass started, drawn, results written (mapped slots)
        std::vector<HemicubeItem> items;
        /// Rows of this slot a pool thread has not summed yet (the slot is not written before 0).
        std::unique_ptr<std::atomic<std::size_t>> rowsLeft = std::make_unique<std::atomic<std::size_t>>(0);
    };
    /// `overlapped`: filled while later passes draw (else the CPU reduction reads into plain memory).
    void makeSlot(Slot& slot, std::uint32_t layers, bool overlapped);
    void releaseSlot(Slot& slot);
    void beginRow(PatchId i, const Vec3& origin, double weight);
    /// Clears the first `count` layers of the atlas (ids, depth, stencil).
    void clearAtlas(std::size_t count);
    /// World -> patch frame of a hemicube at `eye` (scene-centred) with axis `normal`.
    Eigen::Matrix4d frameOf(const Vec3& eye, const Vec3& normal) const;
    void draw(const Pass& pass);
    /// Draws the uploaded instances (m_instances) with the pass's clip plane and winding.
    void drawInstances(const Pass& pass);
    /// Draws a pass of `items` into the next free slot's layers and starts its results.
    void submit(const std::vector<HemicubeItem>& items, HemicubeStats& stats);
    /// After the atlas's first `count` layers are drawn: the commands that fill `slot` (read-back
    /// or GPU reduction), its timestamps and its fence; returns at once (a `host` slot: once read).
    void startResults(Slot& slot, std::size_t count, HemicubeStats& stats);
    /// Blocks until `slot` is filled; adds its GPU times.
    void await(Slot& slot, HemicubeStats& stats);
    template <class RowDone>
    void finishOldest(RowAccumulator& row, RowDone& rowDone, HemicubeStats& stats) {
        Slot& slot = m_slots[m_first];
        {
            const auto lock = lockDriver();
            await(slot, stats);
        }
        if (m_pool) {
            handToPool(slot);
        } else {
            forEachRow(slot.items, [&](std::size_t first, std::size_t last) {
                reduceRow(slot, first, last, row, stats);
                rowDone(slot.items[first].patch);
            });
        }
        m_first = (m_first + 1) % m_slots.size();
        --m_busy;
    }
    /// Calls f(first, last) for each row's run [first, last) of consecutive items.
    template <class F>
    static void forEachRow(const std::vector<HemicubeItem>& items, F&& f) {
        for (std::size_t first = 0; first < items.size();) {
            std::size_t last = first + 1;
            while (last < items.size() && items[last].patch == items[first].patch) ++last;
            f(first, last);
            first = last;
        }
    }
    /// Items [first, last) of a filled slot (one row's hemicubes) into `row`.
    void reduceRow(const Slot& slot, std::size_t first, std::size_t last, RowAccumulator& row,
                   HemicubeStats& stats) const {
        for (std::size_t k = first; k < last; ++k) reduceLayer(slot, k, slot.items.size(), slot.items[k].weight, row, stats);
    }
    /// Posts a filled slot's rows to the pool; the slot is written again only once they are done.
    void handToPool(Slot& slot);
    void readPixels(std::vector<std::uint32_t>& ids, HemicubeStats& stats);
    /// Layer k of a filled slot's `count` into `row`, times weight: from the read-back atlas (CPU)
    /// or the GPU's compacted rows. Reads the slot only: pool threads call it at once.
    void reduceLayer(const Slot& slot, std::size_t k, std::size_t count, double weight, RowAccumulator& row,
                     HemicubeStats& stats) const;
    void reduceIds(const std::uint32_t* ids, double weight, RowAccumulator& row, HemicubeStats& stats) const;
    /// Portal rendering (stencil) for the mirrors seen in `region` of `levelIds`, recursively.
    void traversePortals(int depth, const std::vector<std::uint32_t>& levelIds, const std::vector<std::uint32_t>& region,
                         const Eigen::Matrix4d& transform, double factor, RowAccumulator& row, HemicubeStats& stats);
    void markPortal(std::uint32_t group, int depth, const std::vector<std::uint32_t>& levelIds);
    /// The hybrid variant: every pixel of `ids` (the direct pass) that sees a mirror is traced onwards with Embree.
    void traceMirrorPixels(PatchId i, const std::uint32_t* ids, RowAccumulator& row, HemicubeStats& stats);

    /// `exclusive`, locked if there is one; an empty lock otherwise.
    std::unique_lock<std::mutex> lockDriver() const {
        return m_exclusive ? std::unique_lock<std::mutex>(*m_exclusive) : std::unique_lock<std::mutex>();
    }

    std::mutex* m_exclusive = nullptr;
    /// Held through the constructor, and from the destructor's body until the GL objects below it
    /// are deleted (members go in reverse order).
    std::unique_lock<std::mutex> m_lifetimeLock;
    const Scene& m_scene;
    const HemicubeGeometry& m_geometry;
    const HemicubeLayout& m_layout;
    Reduction m_reduction;
    std::uint32_t m_layers = 1;
    std::size_t m_capacity = 0;  ///< GPU reduction: touched-list length per layer
    gl::Program m_draw[4];  ///< one per HemicubeGeometry::Kind (empty when the scene has none)
    gl::Program m_reduce, m_plan, m_collect, m_portal;
    gl::VertexArray m_vao;
    /// m_layoutBuffer: the GPU reduction's per-layer (count, offset) and its indirect dispatch (device only).
    gl::Buffer m_vertices, m_parents, m_weights, m_accumulator, m_touched, m_layoutBuffer, m_instanceBuffer;
    gl::Texture m_ids, m_depth, m_levelIds;
    gl::Framebuffer m_fbo;
    std::vector<Instance> m_instances;
    /// Passes in flight: a ring of slots, m_busy of them taken from m_first on (submission order).
    std::vector<Slot> m_slots;
    std::size_t m_first = 0, m_busy = 0;
    std::size_t m_inFlight = 1;  ///< passes the GPU may hold (the ring has one more with a pool)
    Slot m_rowSlot;  ///< computeRow's one layer, finished at once
    HemicubeRowPool* m_pool = nullptr;
    std::vector<std::uint32_t> m_pixels;  ///< layer 0 read back for portals after a GPU reduction
    double m_fixedScale = 0;
    MirrorLimits m_limits;
    bool m_mirrors = false;
    /// Mirror patches grouped by plane and reflectance: one portal pass serves a whole group (a
    /// subdivided mirror), with a representative patch for its plane.
    std::vector<std::uint32_t> m_groupOfPatch;  ///< group + 1, 0 for non-mirrors
    std::vector<PatchId> m_groupPatch;
    gl::Buffer m_groups;
    std::array<HemicubeFace, 5> m_faces;  ///< the current row's face cameras
    Vec3 m_eye = Vec3::Zero(), m_normal = Vec3::Zero();  ///< the hemicube's centre (scene-centred) and axis
    double m_weight = 1;  ///< the current hemicube's share of the row
    double m_near = 0;  ///< near plane: 1e-6 of the scene's extent
};

}  // namespace hemirad
