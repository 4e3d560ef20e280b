#pragma once
// gapfe: header-only C++20 finite elements for axisymmetric structures. Umbrella header: everything
// except solver/cholmod.hpp (CHOLMOD is GPL and opt-in), solver/eigen_lu.hpp (the unsymmetric solver:
// include it where a model uses it, so that other translation units do not parse SparseLU) and the PETSc
// policy with its MPI subdomain (solver/petsc.hpp, solver/petsc_subdomain.hpp: the gapfe::petsc target).
// Partitioning itself (mesh/partition.hpp, assembly/partition.hpp, post/gather.hpp) needs no MPI.
#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/contact/policies.hpp"
#include "gapfe/driver/contact_static.hpp"
#include "gapfe/driver/linear_static.hpp"
#include "gapfe/driver/nonlinear_static.hpp"
#include "gapfe/io/deck.hpp"
#include "gapfe/io/deck_output.hpp"
#include "gapfe/io/deck_scene.hpp"
#include "gapfe/io/field_plot.hpp"
#include "gapfe/io/history_file.hpp"
#include "gapfe/io/input_file.hpp"
#include "gapfe/io/run_folder.hpp"
#include "gapfe/io/step_loads.hpp"
#include "gapfe/io/vtu_reader.hpp"
#include "gapfe/io/vtu_writer.hpp"
#include "gapfe/material/drysdale_zak.hpp"
#include "gapfe/material/hill.hpp"
#include "gapfe/mesh/gmsh_mesh.hpp"
#include "gapfe/mesh/gmsh_reader.hpp"
#include "gapfe/mesh/ij_grid.hpp"
#include "gapfe/mesh/structured.hpp"
#include "gapfe/mesh/temperature.hpp"
#include "gapfe/model.hpp"
#include "gapfe/post/gather.hpp"
#include "gapfe/run/deck_run.hpp"
#include "gapfe/solver/runtime_solver.hpp"
#include "gapfe/version.hpp"
