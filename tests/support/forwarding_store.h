#pragma once
// A probe store that forwards every call to another: tests derive from it to change or watch
// one call of a real store and leave the rest as they are.

#include "methods/probe_cache/probe_store.h"

#include <memory>
#include <utility>

namespace gibench::test {

class ForwardingStore : public ProbeStore {
public:
    explicit ForwardingStore(std::unique_ptr<ProbeStore> inner) : m_inner(std::move(inner)) {}

    void prepare(const Scene& scene, RunNotes& notes) override { m_inner->prepare(scene, notes); }
    void beginFrame(const CameraPose& pose, uint32_t frame) override { m_inner->beginFrame(pose, frame); }
    ProbeInsert insert(const ProbeQuery& query, uint32_t frame) override { return m_inner->insert(query, frame); }
    int nearest(const ProbeQuery& query, int count, ProbeNeighbour* out) const override { return m_inner->nearest(query, count, out); }
    void lookup(const ProbeQuery& query, int count, ProbeLookup& out) const override { m_inner->lookup(query, count, out); }
    void lookupBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const override {
        m_inner->lookupBatch(queries, n, count, out);
    }
    void nearestBatch(const ProbeQuery* queries, int n, int count, ProbeNeighbour* out, int* found) const override {
        m_inner->nearestBatch(queries, n, count, out, found);
    }
    int servedAtMost(int count) const override { return m_inner->servedAtMost(count); }
    bool readsJitter() const override { return m_inner->readsJitter(); }
    bool receiverOf(const ProbeQuery& query, uint32_t& id) const override { return m_inner->receiverOf(query, id); }
    bool receiverIsNearest() const override { return m_inner->receiverIsNearest(); }
    void touch(uint32_t id, uint32_t frame) override { m_inner->touch(id, frame); }
    bool admitUpdate(uint32_t id) override { return m_inner->admitUpdate(id); }
    std::span<const Probe> probes() const override { return m_inner->probes(); }
    float coverageRadius(const ProbeQuery& query) const override { return m_inner->coverageRadius(query); }
    float searchRadius(const ProbeQuery& query) const override { return m_inner->searchRadius(query); }
    Json stats() const override { return m_inner->stats(); }

private:
    std::unique_ptr<ProbeStore> m_inner;
};

}  // namespace gibench::test
