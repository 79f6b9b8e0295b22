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
// With capture = "scene" (the default) prepare() captures every card the way Lumen does, by
// projecting the mesh onto it: each texel whose centre a triangle facing the card's direction
// covers gets a probe at the front-most such point (the one seen from outside the box face), with
// the mesh's shading normal there (its geometric normal where the shading normal faces away from
// the card). So the cache covers what the camera does not see, as Lumen's surface cache does, and
// a surface hidden behind another on the same card gets no texel (depth_conflicts when the
// allocation stage asks for one). With capture = "on_demand" cards start empty and only the
// allocation stage places probes.
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
// lookup() is Lumen's: the point projects onto each card of its mesh that faces its way (the
// card of +axis or −axis by the sign of the normal's component, on each axis), weighted by the
// squared component (n_a², summing to 1: a point facing straight along an axis reads one card),
// and on each card the 2×2 texels around its projection are filtered bilinearly between texel
// centres. A texel drops out when it holds no probe, its probe lies beyond depth_tolerance along
// the card's axis (another surface folded onto it) or faces away from the point (n_p·n ≤ 0); the
// pipeline renormalises over what remains. The point is covered when the texel it projects to on
// the card of its dominant direction holds a probe within depth_tolerance: a captured texel.
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

namespace {

enum class Capture { Scene, OnDemand };

const EnumChoices<Capture>& captureChoices() {
    static const EnumChoices<Capture> choices = {{"scene", Capture::Scene}, {"on_demand", Capture::OnDemand}};
    return choices;
}

}  // namespace

const ParamTable& cardsStoreParams() {
    static const ParamTable table = joinTables(
        spacingParams("texel_size", "card texel edge"),
        {
            {"capture", ParamType::String, "scene",
             "card texels with probes: every texel captured from the meshes in prepare (Lumen), or only where the allocation stage asks",
             -INFINITY, INFINITY, choiceNames(captureChoices())},
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

// lookup() reads 2×2 texels on each of up to 3 cards.
constexpr int kCardTexelsServed = 12;
static_assert(kCardTexelsServed <= kMaxServedProbes);

struct CardsSettings {
    ProbeSpacing texelSize;
    Capture capture = Capture::Scene;
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

// A point projected onto a card, in texel edges from the card's origin along its u and v axes.
struct CardPoint {
    double u, v;
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
        m_texelSize = m_settings.texelSize.resolve(bounds);
        m_texelsPerUnit = 1.0 / double(m_texelSize);
        if (bounds.empty()) {
            notes.skip("probes", "the scene has no geometry: no cards");
            return;
        }

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
        if (m_settings.capture == Capture::Scene)
            for (const Planned& p : planned)
                captureCard(scene.meshes[std::size_t(p.mesh)], m_cards[std::size_t(m_cardOf[std::size_t(p.mesh) * 6 + std::size_t(p.direction)])],
                            p.direction);
        m_capturedAtPrepare = m_probes.size();
        notes.skip("probe_recycling",
                   "cards: a texel keeps its first probe; a surface that box projection folds onto an occupied texel at another depth "
                   "gets none (depth_conflicts)");
    }

    // Lumen's card capture, by texel centres: the front-most point of the mesh's triangles facing
    // `direction` at each texel, seen from outside the card's box face.
    void captureCard(const Mesh& mesh, const Card& card, int direction) {
        const int axis = card.axis, axisU = (axis + 1) % 3, axisV = (axis + 2) % 3;
        const float outward = direction % 2 == 0 ? 1.0f : -1.0f;
        const std::size_t texels = std::size_t(card.width * card.height);
        std::vector<float> front(texels, -kInfinity);  // outward × depth of the point kept so far
        std::vector<Probe> captured(texels);
        for (const uvec3& t : mesh.indices) {
            const vec3 p[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
            const vec3 geometric = glm::cross(p[1] - p[0], p[2] - p[0]);
            if (dominantDirection(geometric) != direction) continue;
            // Vertices in texel units on the card, texel centres on half-integers.
            vec2 q[3];
            for (int k = 0; k < 3; ++k)
                q[k] = {(p[k][axisU] - card.origin[axisU]) / m_texelSize, (p[k][axisV] - card.origin[axisV]) / m_texelSize};
            const float area = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[1].y - q[0].y) * (q[2].x - q[0].x);
            if (!(std::fabs(area) > 0.0f)) continue;
            const vec3 unitGeometric = glm::normalize(geometric);
            const int64_t u0 = std::max<int64_t>(int64_t(std::ceil(std::min({q[0].x, q[1].x, q[2].x}) - 0.5f)), 0);
            const int64_t u1 = std::min<int64_t>(int64_t(std::floor(std::max({q[0].x, q[1].x, q[2].x}) - 0.5f)), card.width - 1);
            const int64_t v0 = std::max<int64_t>(int64_t(std::ceil(std::min({q[0].y, q[1].y, q[2].y}) - 0.5f)), 0);
            const int64_t v1 = std::min<int64_t>(int64_t(std::floor(std::max({q[0].y, q[1].y, q[2].y}) - 0.5f)), card.height - 1);
            for (int64_t v = v0; v <= v1; ++v)
                for (int64_t u = u0; u <= u1; ++u) {
                    const vec2 c(float(u) + 0.5f, float(v) + 0.5f);
                    // Barycentric coordinates of the texel centre; on an edge it belongs to both triangles.
                    float b[3];
                    for (int k = 0; k < 3; ++k) {
                        const vec2& a = q[(k + 1) % 3];
                        const vec2& e = q[(k + 2) % 3];
                        b[k] = ((e.x - a.x) * (c.y - a.y) - (e.y - a.y) * (c.x - a.x)) / area;
                    }
                    if (b[0] < 0.0f || b[1] < 0.0f || b[2] < 0.0f) continue;
                    const vec3 position = b[0] * p[0] + b[1] * p[1] + b[2] * p[2];
                    const std::size_t texel = std::size_t(v * card.width + u);
                    if (!(outward * position[axis] > front[texel])) continue;
                    vec3 normal = unitGeometric;
                    if (!mesh.normals.empty()) {
                        const vec3 shading = b[0] * mesh.normals[t.x] + b[1] * mesh.normals[t.y] + b[2] * mesh.normals[t.z];
                        const float length = glm::length(shading);
                        if (length > 0.0f && outward * shading[axis] > 0.0f) normal = shading / length;
                    }
                    front[texel] = outward * position[axis];
                    captured[texel] = {position, normal};
                }
        }
        for (std::size_t texel = 0; texel < texels; ++texel) {
            if (front[texel] == -kInfinity) continue;
            m_atlas[card.offset + texel] = uint32_t(m_probes.size());
            m_probes.push_back(captured[texel]);
            m_admittedFrame.push_back(0);
        }
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

    void lookup(const ProbeQuery& query, int count, ProbeLookup& out) const override {
        out.count = 0;
        out.covered = false;
        out.distance = kInfinity;
        out.receiver = kReceiverUnknown;
        if (!isSurfaceQuery(query)) return;
        for (int axis = 0; axis < 3; ++axis) {
            const float component = query.normal[axis];
            const float cardWeight = component * component;
            if (!(cardWeight > 0.0f)) continue;
            const int32_t index = m_cardOf[std::size_t(query.mesh) * 6 + std::size_t(2 * axis + (component < 0.0f ? 1 : 0))];
            if (index >= 0) filterCard(m_cards[std::size_t(index)], query, cardWeight, out);
        }
        normaliseWeights(out);
        if (const Card* card = cardOf(query)) out.covered = coveredAt(*card, projectOnto(*card, query.position), query);
    }
    int servedAtMost(int count) const override { return kCardTexelsServed; }

    // Adds the card's 2×2 texels around the query's projection, bilinearly weighted and scaled by
    // `cardWeight`, to `out`.
    void filterCard(const Card& card, const ProbeQuery& query, float cardWeight, ProbeLookup& out) const {
        const CardPoint at = projectOnto(card, query.position);
        // Texel coordinates with texel centres on integers.
        const double fu = at.u - 0.5, fv = at.v - 0.5;
        // A point more than a texel off the card reads nothing (as texelAt); compared as doubles
        // first, so that a point far away does not overflow the integer conversion.
        if (!(fu >= -1.5 && fu <= double(card.width) + 0.5 && fv >= -1.5 && fv <= double(card.height) + 0.5)) return;
        const double u0 = std::floor(fu), v0 = std::floor(fv);
        const float du = float(fu - u0), dv = float(fv - v0);
        const int64_t us[2] = {std::clamp(int64_t(u0), int64_t(0), card.width - 1), std::clamp(int64_t(u0) + 1, int64_t(0), card.width - 1)};
        const int64_t vs[2] = {std::clamp(int64_t(v0), int64_t(0), card.height - 1), std::clamp(int64_t(v0) + 1, int64_t(0), card.height - 1)};
        // Only texels clamped at the card's border can name one probe twice (their weights add up):
        // a probe owns one texel, of one card.
        const bool clamped = us[0] == us[1] || vs[0] == vs[1];
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
                const uint32_t id = m_atlas[card.offset + std::size_t(vs[j] * card.width + us[i])];
                if (id == kNoProbe) continue;
                const Probe& p = m_probes[id];
                if (!withinDepth(card, p, query) || !(glm::dot(p.normal, query.normal) > 0.0f)) continue;
                const float bilinear = (i ? du : 1.0f - du) * (j ? dv : 1.0f - dv);
                const float weight = cardWeight * bilinear, distance = glm::length(p.position - query.position);
                out.distance = std::min(out.distance, distance);
                if (!clamped || !addToServed(out, id, weight)) out.probes[out.count++] = {id, weight};
            }
    }

    // Whether the texel the query projects to (at `at`) holds a probe within depth: what makes
    // insert() refuse it as occupied.
    bool coveredAt(const Card& card, const CardPoint& at, const ProbeQuery& query) const {
        int64_t u, v;
        if (!texelAt(card, at, u, v)) return false;
        const uint32_t id = m_atlas[card.offset + std::size_t(v * card.width + u)];
        return id != kNoProbe && withinDepth(card, m_probes[id], query);
    }

    // Adds `weight` to probe `id` if `out` already serves it.
    static bool addToServed(ProbeLookup& out, uint32_t id, float weight) {
        for (int k = 0; k < out.count; ++k)
            if (out.probes[k].id == id) {
                out.probes[k].weight += weight;
                return true;
            }
        return false;
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

    std::span<const Probe> probes() const override { return m_probes; }

    // One probe per texel-sized disc: the density of the dense grid's and MAMBA's cells at the same edge.
    float coverageRadius(const ProbeQuery&) const override { return m_texelSize; }
    // kSearchRings texel edges: the (2 kSearchRings + 1)² texels around the query hold every probe of its card this close.
    float searchRadius(const ProbeQuery&) const override { return kSearchRings * m_texelSize; }

    Json stats() const override {
        const std::size_t bytes = m_atlas.capacity() * sizeof(uint32_t) + m_probes.capacity() * sizeof(Probe) +
                                  m_admittedFrame.capacity() * sizeof(uint32_t) + m_cards.capacity() * sizeof(Card) +
                                  m_cardOf.capacity() * sizeof(int32_t);
        return {
            {"probes", m_probes.size()},
            {"texel_size", m_texelSize},
            {"cards", m_cards.size()},
            {"captured_at_prepare", m_capturedAtPrepare},
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

    // `p` projected onto the card.
    CardPoint projectOnto(const Card& card, const vec3& p) const {
        const int axisU = (card.axis + 1) % 3, axisV = (card.axis + 2) % 3;
        return {(double(p[axisU]) - double(card.origin[axisU])) * m_texelsPerUnit, (double(p[axisV]) - double(card.origin[axisV])) * m_texelsPerUnit};
    }

    // The texel (u, v) finite `p` projects to, or false when it lies more than a texel off the card.
    bool texelOf(const Card& card, const vec3& p, int64_t& u, int64_t& v) const { return texelAt(card, projectOnto(card, p), u, v); }
    bool texelAt(const Card& card, const CardPoint& at, int64_t& u, int64_t& v) const {
        const double fu = std::floor(at.u), fv = std::floor(at.v);
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
    double m_texelsPerUnit = 0.0;  // 1 / m_texelSize: a projection multiplies rather than divides
    std::size_t m_meshCount = 0;
    std::vector<Card> m_cards;
    std::vector<int32_t> m_cardOf;          // 6 per mesh, by dominantDirection(): index into m_cards or -1
    std::vector<uint32_t> m_atlas;          // per texel: the probe id or kNoProbe
    std::vector<Probe> m_probes;            // by id
    std::vector<uint32_t> m_admittedFrame;  // by id: the epoch of the last frame its texel was admitted an update
    uint32_t m_epoch = 1;                   // advanced by beginFrame(); 0 marks "never admitted"
    uint32_t m_updatesThisFrame = 0, m_capturesThisFrame = 0;
    std::size_t m_capturedAtPrepare = 0;
    uint64_t m_depthConflicts = 0, m_texelOccupied = 0, m_noCard = 0, m_invalidQueries = 0, m_captureRejections = 0,
             m_budgetRejections = 0;
};

}  // namespace

std::unique_ptr<ProbeStore> createCardsStore(Params& params) {
    CardsSettings s;
    s.texelSize = ProbeSpacing(params, "texel_size");
    s.capture = params.getEnum("capture", captureChoices());
    s.depthTolerance = params.getFloat("depth_tolerance");
    s.updateBudget = uint32_t(params.getInt("texel_update_budget"));
    s.captureBudget = uint32_t(params.getInt("texel_capture_budget"));
    s.maxAtlasTexels = double(params.getInt("max_atlas_texels"));
    s.maxAtlasTexelsWhere = params.where("max_atlas_texels");
    return std::make_unique<CardsStore>(std::move(s));
}

}  // namespace gibench
