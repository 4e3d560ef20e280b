#pragma once
// Model: one alias picks a variant at compile time. Each policy is checked by its concept here, so a
// wrong plug-in fails at the alias rather than deep in the assembler.
#include "gapfe/core/concepts.hpp"
#include "gapfe/element/legacy_quad.hpp"
#include "gapfe/element/quad4.hpp"
#include "gapfe/element/quad8.hpp"
#include "gapfe/element/tri3.hpp"
#include "gapfe/element/tri6.hpp"
#include "gapfe/kinematics/axisym2.hpp"
#include "gapfe/kinematics/axisym3.hpp"
#include "gapfe/material/elastic.hpp"
#include "gapfe/solver/eigen_ldlt.hpp"

namespace gapfe {

template <class Kin, class Elem, class Law, class Solver = EigenLdlt>
requires KinematicsFor<Kin, Elem> && MaterialLaw<Law> && LinearSolver<Solver>
struct Model {
  using Kinematics                  = Kin;
  using Element                     = Elem;
  using Material                    = Law;
  using LinearSolver                = Solver;
  static constexpr int kDofsPerNode = Kin::kDofsPerNode;
};

// The seed's code names, mirrored on purpose (BRL-CR-670 section 2.1): SAAS is the 2-DOF axisymmetric
// code, SAGA its 3-DOF extension; both with the legacy four-CST quadrilateral and orthotropic material.
using Saas = Model<Axisym2, LegacyQuad, Orthotropic>;
using Saga = Model<Axisym3, LegacyQuad, Orthotropic>;

}  // namespace gapfe
