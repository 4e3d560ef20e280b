#pragma once
// gapfe: header-only C++20 finite elements for axisymmetric structures. Umbrella header: everything
// except solver/cholmod.hpp (CHOLMOD is GPL and opt-in), solver/eigen_lu.hpp (the unsymmetric solver:
// include it where a model uses it, so that other translation units do not parse SparseLU) and the PETSc
// policy with its MPI subdomain (solver/petsc.hpp, solver/petsc_subdomain.hpp: the gapfe::petsc target).
// Partitioning itself (mesh/cell_partition.hpp, assembly/problem_part.hpp, post/gather.hpp) needs no MPI.
#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/contact/policies.hpp"
#include "gapfe/driver/contact_static.hpp"
#include "gapfe/driver/linear_static.hpp"
#include "gapfe/driver/nonlinear_static.hpp"
#include "gapfe/input/deck.hpp"
#include "gapfe/input/deck_scene.hpp"
#include "gapfe/input/gmsh_mesh.hpp"
#include "gapfe/input/gmsh_reader.hpp"
#include "gapfe/input/input_file.hpp"
#include "gapfe/input/vtu_reader.hpp"
#include "gapfe/material/drysdale_zak.hpp"
#include "gapfe/material/hill.hpp"
#include "gapfe/mesh/ij_grid.hpp"
#include "gapfe/mesh/structured.hpp"
#include "gapfe/mesh/temperature.hpp"
#include "gapfe/output/field_plot.hpp"
#include "gapfe/output/history_file.hpp"
#include "gapfe/output/run_folder.hpp"
#include "gapfe/output/step_files.hpp"
#include "gapfe/output/vtu_writer.hpp"
#include "gapfe/post/gather.hpp"
#include "gapfe/problem/model.hpp"
#include "gapfe/run/deck_run.hpp"
#include "gapfe/run/step_loads.hpp"
#include "gapfe/solver/runtime_solver.hpp"
#include "gapfe/version.hpp"
