#pragma once
// Expectations on a repaired mesh, shared by the repair tests on generated and on shared meshes.

#include <gtest/gtest.h>

#include "core/mesh/report.h"

namespace hexcover::test {

/// A repaired mesh is manifold, consistently oriented and free of the defects repair removes.
inline void expectManifoldAndOriented(const MeshStatistics& s) {
  EXPECT_EQ(s.nonManifoldEdges, 0u);
  EXPECT_EQ(s.nonManifoldVertices, 0u);
  EXPECT_EQ(s.inconsistentlyOrientedEdges, 0u);
  EXPECT_EQ(s.nonOrientableComponents, 0u);
  EXPECT_EQ(s.degenerateFaces, 0u);
  EXPECT_EQ(s.duplicateFaces, 0u);
  EXPECT_EQ(s.unreferencedVertices, 0u);
}

}  // namespace hexcover::test
