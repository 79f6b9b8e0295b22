// Probe store "cards" (Lumen-like surface cache, MAMBA paper §3.2): rectangular arrays of probe
// texels laid on the surfaces. prepare() places up to 6 cards per mesh by axis-aligned box
// projection, one per face (±X, ±Y, ±Z) of the mesh's bounding box that some triangle of the mesh
// faces (the dominant axis and sign of its geometric normal, counter-clockwise front). A card is a
// grid of texel_size texels over its box face, and all cards are packed into one atlas: a flat
// array holding a probe id or none per texel, allocated whole, so its memory grows with the area
// of the meshes' box faces (for boxy meshes, their surface area) rather than the scene's volume.
//
// Memory (stats "store_bytes"): 4 bytes per atlas texel (a probe id) from prepare() on, 28 bytes per
// probe (position and normal, and the frame its texel last took an update), 40 bytes per card
// and 24 bytes per mesh (its 6 card slots); std::vector capacities.
//
// A query picks its card by its mesh and the dominant axis and sign of its normal (which faces
// the viewer), and its texel by projecting its position onto the card; a point up to one texel
// off the card's rectangle maps to the border texel. No card, or no texel: no probe (no_card).
//
// insert() creates the probe of the query's texel, at the query's position and normal (the probe
// sits on the surface that asked), or refuses and counts why: the texel already holds a probe
// within depth_tolerance along the card's axis (texel_occupied) or beyond it, on another surface
// that box projection folds onto the same texel, Lumen's known limitation (depth_conflicts); the
// query has no card texel (no_card) or names no surface point (invalid_queries: mesh out of
// range, non-finite position or normal); texel_capture_budget probes were already created this
// frame (capture_budget_rejections; Lumen also budgets card captures per frame, apart from
// lighting updates). A texel keeps its first probe for the whole run.
//
// nearest() offers the probes of the query's card that lie within depth_tolerance along the
// card's axis and within searchRadius() = kSearchRings texel edges, nearest first. The (2k+1)²
// texels around the query's texel hold every probe of the card within k edges: a probe sits in
// the texel its own position projects to (clamped at the border), and a point within k texel
// edges of the query is within k edges along each card axis, hence at most k texel indices away.
// So the answer never depends on where inside its texel the query falls. The 3×3 texels (k = 1)
// are searched first and settle the query when they already hold enough probes within one edge.
//
// admitUpdate(id) accepts an update of probe id's texel when the texel was already admitted this
// frame, or while fewer than texel_update_budget distinct texels were admitted; otherwise it
// refuses and counts (budget_rejections). beginFrame() resets both budgets.

#include "methods/probe_cache/stores/cards/cards_store.h"

#include "core/util/error.h"
#include "core/util/text_format.h"
#include "methods/probe_cache/probe_spacing.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace gibench {

const ParamTable& cardsStoreParams() {
    static const ParamTable table = joinTables(
        spacingParams("texel_size", "card texel edge"),
        {
            {"depth_tolerance", ParamType::Float, 2.0,
             "in texels: a texel's probe serves only points within this distance of it along the card's axis", 0.0},
            {"texel_update_budget", ParamType::Int, 4096, "distinct card texels that may take updates per frame", 1, 1 << 30},
            {"texel_capture_budget", ParamType::Int, 4096, "probes created in card texels per frame", 1, 1 << 30},
            {"max_atlas_texels", ParamType::Int, 1 << 24, "card texels at most; the atlas is allocated whole", 1,
             double(std::numeric_limits<uint32_t>::max())},
        },
        "cards");
    return table;
}

namespace {

constexpr uint32_t kNoProbe = std::numeric_limits<uint32_t>::max();

struct CardsSettings {
    ProbeSpacing texelSize;
    float depthTolerance = 0.0f;  // texels
    uint32_t updateBudget = 0;
    uint32_t captureBudget = 0;
    double maxAtlasTexels = 0.0;
    // "FILE: /pointer/key: " prefixes for the errors only prepare() can find.
    std::string maxAtlasTexelsWhere;
};

// One face of a mesh's bounding box covered with texels.
struct Card {
    int axis = 0;           // the card faces along +axis or -axis; its texels run along u = axis + 1, v = axis + 2 (mod 3)
    vec3 origin{0.0f};      // the mesh's bounding-box minimum: texel (0, 0) starts there
    int64_t width = 0;      // texels along u
    int64_t height = 0;     // texels along v
    std::size_t offset = 0; // first texel in the atlas; rows of `width` texels, one per v
};

class CardsStore final : public ProbeStore {
public:
    explicit CardsStore(CardsSettings settings) : m_settings(std::move(settings)) {}

    void prepare(const Scene& scene, RunNotes& notes) override {
        m_cards.clear();
        m_atlas.clear();
        m_probes.clear();
        m_admittedFrame.clear();
        m_meshCount = scene.meshes.size();
        m_cardOf.assign(m_meshCount * 6, -1);
        m_depthConflicts = m_texelOccupied = m_noCard = m_invalidQueries = m_captureRejections = m_budgetRejections = 0;
        m_updatesThisFrame = m_capturesThisFrame = 0;

        const Bounds3 bounds = scene.bounds();
        if (bounds.empty()) {
            m_texelSize = m_settings.texelSize.resolve(bounds);
            notes.skip("probes", "the scene has no geometry: no cards");
            return;
        }
        m_texelSize = m_settings.texelSize.resolve(bounds);

        // Sizes are counted in double first: a layout too large to allocate must not overflow an integer.
        struct Planned {
            int mesh, direction;
            Bounds3 box;
            double width, height;
        };
        std::vector<Planned> planned;
        double texels = 0.0;
        for (std::size_t m = 0; m < m_meshCount; ++m) {
            const Mesh& mesh = scene.meshes[m];
            Bounds3 box;
            bool faces[6] = {false, false, false, false, false, false};
            for (const uvec3& t : mesh.indices) {
                const vec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
                box.extend(a);
                box.extend(b);
                box.extend(c);
                const int direction = dominantDirection(glm::cross(b - a, c - a));
                if (direction >= 0) faces[direction] = true;
            }
            const vec3 extent = box.extent();
            for (int direction = 0; direction < 6; ++direction) {
                if (!faces[direction]) continue;
                const int axis = direction / 2;
                const double width = std::max(1.0, std::ceil(double(extent[(axis + 1) % 3]) / double(m_texelSize)));
                const double height = std::max(1.0, std::ceil(double(extent[(axis + 2) % 3]) / double(m_texelSize)));
                planned.push_back({int(m), direction, box, width, height});
                texels += width * height;
            }
        }
        if (texels > m_settings.maxAtlasTexels)
            throw InputError(m_settings.maxAtlasTexelsWhere + "the scene's " + std::to_string(planned.size()) + " cards need " +
                             formatCount(texels) + " texels of " + formatNumber(m_texelSize) + " units, more than max_atlas_texels = " +
                             formatCount(m_settings.maxAtlasTexels) + "; raise max_atlas_texels or the texel size");

        m_cards.reserve(planned.size());
        std::size_t offset = 0;
        for (const Planned& p : planned) {
            Card card;
            card.axis = p.direction / 2;
            card.origin = p.box.min;
            card.width = int64_t(p.width);
            card.height = int64_t(p.height);
            card.offset = offset;
            offset += std::size_t(card.width * card.height);
            m_cardOf[std::size_t(p.mesh) * 6 + std::size_t(p.direction)] = int32_t(m_cards.size());
            m_cards.push_back(card);
        }
        m_atlas.assign(offset, kNoProbe);
        notes.skip("probe_recycling",
                   "cards: a texel keeps its first probe; a surface that box projection folds onto an occupied texel at another depth "
                   "gets none (depth_conflicts)");
    }

    void beginFrame(const CameraPose& pose, uint32_t frame) override {
        ++m_epoch;
        m_updatesThisFrame = 0;
        m_capturesThisFrame = 0;
    }

    ProbeInsert insert(const ProbeQuery& query, uint32_t frame) override {
        if (!isSurfaceQuery(query)) {
            ++m_invalidQueries;
            return {ProbeInsert::Status::Refused};
        }
        const Card* card = cardOf(query);
        int64_t u, v;
        if (!card || !texelOf(*card, query.position, u, v)) {
            ++m_noCard;
            return {ProbeInsert::Status::Refused};
        }
        uint32_t& slot = m_atlas[card->offset + std::size_t(v * card->width + u)];
        if (slot != kNoProbe) {
            if (withinDepth(*card, m_probes[slot], query))
                ++m_texelOccupied;
            else
                ++m_depthConflicts;
            return {ProbeInsert::Status::Refused};
        }
        if (m_capturesThisFrame == m_settings.captureBudget) {
            ++m_captureRejections;
            return {ProbeInsert::Status::Refused};
        }
        const uint32_t id = uint32_t(m_probes.size());
        m_probes.push_back({query.position, query.normal});
        m_admittedFrame.push_back(0);
        slot = id;
        ++m_capturesThisFrame;
        return {ProbeInsert::Status::Inserted, id};
    }

    int nearest(const ProbeQuery& query, int count, ProbeNeighbour* out) const override {
        if (count <= 0 || !isSurfaceQuery(query)) return 0;
        const Card* card = cardOf(query);
        int64_t cu, cv;
        if (!card || !texelOf(*card, query.position, cu, cv)) return 0;
        // The 3×3 texels settle the query when they hold `count` probes within one texel edge;
        // otherwise the 5×5 texels, sound up to two edges.
        const int found = nearestOnCard(*card, cu, cv, query, count, out, 1);
        if (found == count && out[count - 1].distance <= m_texelSize) return found;
        return nearestOnCard(*card, cu, cv, query, count, out, kSearchRings);
    }

    // Probes of the card within `rings` texel edges, from the (2 rings + 1)² texels around (cu, cv).
    int nearestOnCard(const Card& card, int64_t cu, int64_t cv, const ProbeQuery& query, int count, ProbeNeighbour* out, int rings) const {
        const float radius = float(rings) * m_texelSize;
        int found = 0;
        for (int64_t v = std::max<int64_t>(cv - rings, 0); v <= std::min(cv + rings, card.height - 1); ++v)
            for (int64_t u = std::max<int64_t>(cu - rings, 0); u <= std::min(cu + rings, card.width - 1); ++u) {
                const uint32_t id = m_atlas[card.offset + std::size_t(v * card.width + u)];
                if (id == kNoProbe) continue;
                const Probe& p = m_probes[id];
                if (!withinDepth(card, p, query)) continue;
                const float distance = glm::length(p.position - query.position);
                if (!(distance <= radius)) continue;
                found = insertNearest(out, found, count, {id, distance});
            }
        return found;
    }

    // Called from one thread, like insert(). A probe owns one texel for the whole run, so distinct
    // probes are distinct texels.
    bool admitUpdate(uint32_t id) override {
        if (id >= m_probes.size()) return false;
        if (m_admittedFrame[id] == m_epoch) return true;
        if (m_updatesThisFrame == m_settings.updateBudget) {
            ++m_budgetRejections;
            return false;
        }
        m_admittedFrame[id] = m_epoch;
        ++m_updatesThisFrame;
        return true;
    }

    const Probe& probe(uint32_t id) const override { return m_probes[id]; }
    uint32_t idCapacity() const override { return uint32_t(m_probes.size()); }

    // One probe per texel-sized disc: the density of the dense grid's and MAMBA's cells at the same edge.
    float coverageRadius() const override { return m_texelSize; }
    // kSearchRings texel edges: the (2 kSearchRings + 1)² texels around the query hold every probe of its card this close.
    float searchRadius() const override { return kSearchRings * m_texelSize; }

    Json stats() const override {
        const std::size_t bytes = m_atlas.capacity() * sizeof(uint32_t) + m_probes.capacity() * sizeof(Probe) +
                                  m_admittedFrame.capacity() * sizeof(uint32_t) + m_cards.capacity() * sizeof(Card) +
                                  m_cardOf.capacity() * sizeof(int32_t);
        return {
            {"probes", m_probes.size()},
            {"texel_size", m_texelSize},
            {"cards", m_cards.size()},
            {"atlas_texels", m_atlas.size()},
            {"store", "cards"},
            {"store_bytes", bytes},
            {"refused", m_depthConflicts + m_texelOccupied + m_noCard + m_invalidQueries + m_captureRejections},
            {"depth_conflicts", m_depthConflicts},
            {"texel_occupied", m_texelOccupied},
            {"no_card", m_noCard},
            {"invalid_queries", m_invalidQueries},
            {"capture_budget_rejections", m_captureRejections},
            {"budget_rejections", m_budgetRejections},
            {"frame_captures", m_capturesThisFrame},
            {"frame_updates", m_updatesThisFrame},
        };
    }

private:
    // A query names a surface point: a mesh of the scene, a finite position and a finite normal.
    bool isSurfaceQuery(const ProbeQuery& query) const {
        return query.mesh >= 0 && std::size_t(query.mesh) < m_meshCount && isFinite(query.position) && isFinite(query.normal);
    }

    // The card of the query's mesh facing its normal's dominant direction, or null.
    const Card* cardOf(const ProbeQuery& query) const {
        const int direction = dominantDirection(query.normal);
        if (direction < 0) return nullptr;
        const int32_t index = m_cardOf[std::size_t(query.mesh) * 6 + std::size_t(direction)];
        return index < 0 ? nullptr : &m_cards[std::size_t(index)];
    }

    // The texel (u, v) finite `p` projects to, or false when it lies more than a texel off the card.
    bool texelOf(const Card& card, const vec3& p, int64_t& u, int64_t& v) const {
        const int axisU = (card.axis + 1) % 3, axisV = (card.axis + 2) % 3;
        const double fu = std::floor((double(p[axisU]) - double(card.origin[axisU])) / double(m_texelSize));
        const double fv = std::floor((double(p[axisV]) - double(card.origin[axisV])) / double(m_texelSize));
        // Compared as doubles first: a point far away must not overflow the integer conversion.
        if (!(fu >= -1.0 && fu <= double(card.width) && fv >= -1.0 && fv <= double(card.height))) return false;
        u = std::clamp(int64_t(fu), int64_t(0), card.width - 1);
        v = std::clamp(int64_t(fv), int64_t(0), card.height - 1);
        return true;
    }

    // Whether probe `p` may serve the query: box projection folds every surface of the mesh facing
    // the card's way onto it, and a probe at another depth belongs to another surface.
    bool withinDepth(const Card& card, const Probe& p, const ProbeQuery& query) const {
        return std::fabs(p.position[card.axis] - query.position[card.axis]) <= m_settings.depthTolerance * m_texelSize;
    }

    CardsSettings m_settings;
    float m_texelSize = 0.0f;  // resolved in prepare(), scene units
    std::size_t m_meshCount = 0;
    std::vector<Card> m_cards;
    std::vector<int32_t> m_cardOf;          // 6 per mesh, by dominantDirection(): index into m_cards or -1
    std::vector<uint32_t> m_atlas;          // per texel: the probe id or kNoProbe
    std::vector<Probe> m_probes;            // by id
    std::vector<uint32_t> m_admittedFrame;  // by id: the epoch of the last frame its texel was admitted an update
    uint32_t m_epoch = 1;                   // advanced by beginFrame(); 0 marks "never admitted"
    uint32_t m_updatesThisFrame = 0, m_capturesThisFrame = 0;
    uint64_t m_depthConflicts = 0, m_texelOccupied = 0, m_noCard = 0, m_invalidQueries = 0, m_captureRejections = 0,
             m_budgetRejections = 0;
};

}  // namespace

std::unique_ptr<ProbeStore> createCardsStore(Params& params) {
    CardsSettings s;
    s.texelSize = ProbeSpacing(params, "texel_size");
    s.depthTolerance = params.getFloat("depth_tolerance");
    s.updateBudget = uint32_t(params.getInt("texel_update_budget"));
    s.captureBudget = uint32_t(params.getInt("texel_capture_budget"));
    s.maxAtlasTexels = double(params.getInt("max_atlas_texels"));
    s.maxAtlasTexelsWhere = params.where("max_atlas_texels");
    return std::make_unique<CardsStore>(std::move(s));
}

}  // namespace gibench
