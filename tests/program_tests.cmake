## Tests that run the program (driven by Debian's python3, which has vtk).
find_program(ISOIMPACT_PYTHON python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT ISOIMPACT_PYTHON)
  find_program(ISOIMPACT_PYTHON python3)
endif()
set(_scripts ${CMAKE_CURRENT_SOURCE_DIR}/scripts)
set(_work ${CMAKE_CURRENT_BINARY_DIR}/program_tests)

add_test(NAME hertz_fea_hrz_benchmark
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/hertz_benchmark.py
    $<TARGET_FILE:isoimpact_program>
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm ${_work})
set_tests_properties(hertz_fea_hrz_benchmark PROPERTIES
  TIMEOUT 600 FIXTURES_SETUP hertz_output)

add_test(NAME hertz_iga_consistent_benchmark
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/hertz_benchmark.py
    $<TARGET_FILE:isoimpact_program>
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_consistent_coarse.prm ${_work})
set_tests_properties(hertz_iga_consistent_benchmark PROPERTIES TIMEOUT 600)

add_test(NAME vtu_readback
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/vtu_readback.py
    ${_work}/hertz_fea_hrz_coarse)
set_tests_properties(vtu_readback PROPERTIES FIXTURES_REQUIRED hertz_output)

# The parts of the wall time in summary.json add up to the total.
add_test(NAME summary_wall_time
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/summary_wall_time.py
    ${_work}/hertz_fea_hrz_coarse)
set_tests_properties(summary_wall_time PROPERTIES FIXTURES_REQUIRED hertz_output)

# Higher-order VTU cells read back with VTK: rational Bezier arcs exact to
# 1e-12, quadratic Lagrange arcs within their interpolation bound.
add_test(NAME vtu_higher_order
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/vtu_higher_order.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_CURRENT_SOURCE_DIR}/prm
    ${_work}/vtu_higher_order)
set_tests_properties(vtu_higher_order PROPERTIES TIMEOUT 300)

# The contact pressure field of the ParaView output equals the consistent
# pressure of the profile CSV at its Gauss points (issue 11).
add_test(NAME vtu_contact_pressure
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/vtu_contact_pressure.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_CURRENT_SOURCE_DIR}/prm
    ${_work}/vtu_contact_pressure)
set_tests_properties(vtu_contact_pressure PROPERTIES TIMEOUT 300)

# The filtered peaks of summary.json against the Python filter applied to
# history.csv (the fixture's run writes every step: History interval = 1).
add_test(NAME filtered_peak_summary_vs_history
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/filtered_peak.py
    ${_work}/hertz_fea_hrz_coarse)
set_tests_properties(filtered_peak_summary_vs_history PROPERTIES
  FIXTURES_REQUIRED hertz_output)

add_test(NAME bad_input
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/bad_input.py
    $<TARGET_FILE:isoimpact_program>
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm ${_work}/bad_input)

# The stable step and the stability monitor at the extremes (issue 9; the
# full tables are in doc/stability.md).
foreach(_group refusal bound penalty material channel)
  add_test(NAME stability_extremes_${_group}
    COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/stability_extremes.py
      $<TARGET_FILE:isoimpact_program>
      ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm
      ${_work}/stability_${_group} ${_group})
  set_tests_properties(stability_extremes_${_group} PROPERTIES TIMEOUT 900)
endforeach()

# The oscillation measure of the study (doc/oscillation.md) on synthetic
# signals with known answers.
add_test(NAME oscillation_measure
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/oscillation_measure.py)

# The study driver on the coarse scenes: figures and results table.
add_test(NAME hertz_study_figures
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/hertz_study_figures.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_SOURCE_DIR}/scripts/hertz_study.py
    ${_work}/hertz_study
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_consistent_coarse.prm
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_rowsum_coarse.prm)
set_tests_properties(hertz_study_figures PROPERTIES TIMEOUT 600)

# Users' programs (examples/<name>) built against the exported package, as a
# user would, and run; each exits non-zero on a failed assertion.
function(isoimpact_add_example_test test_name example)
  add_test(NAME ${test_name}
    COMMAND ${CMAKE_CTEST_COMMAND}
      --build-and-test ${CMAKE_SOURCE_DIR}/examples/${example}
                       ${CMAKE_CURRENT_BINARY_DIR}/example_${example}
      --build-generator ${CMAKE_GENERATOR}
      --build-options -Disoimpact_DIR=${CMAKE_BINARY_DIR}
                      -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE}
      --test-command ${example})
  set_tests_properties(${test_name} PROPERTIES TIMEOUT 900)
endfunction()

# A standing elastic wave (FE_Q(2)): energy drift.
isoimpact_add_example_test(example_builds_against_library elastic_wave)
# FE_NURBS on a quarter annulus: L2 error.
isoimpact_add_example_test(example_nurbs_builds_against_library
  nurbs_quarter_annulus)
# The isogeometric impact (two NURBS half cylinders, two-pass penalty
# contact, central differences): the contact duration against the analytic
# Hertz impact to 2 %.
isoimpact_add_example_test(example_nurbs_impact_builds_against_library
  nurbs_impact)

# Scene reduction: one half cylinder against the rigid plane y = 0 against
# the two-body run (same mesh, mass, time step; FEA and IGA), and against a
# rigid cylinder.
add_test(NAME rigid_obstacle_reduction
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/rigid_obstacle_reduction.py
    $<TARGET_FILE:isoimpact_program>
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_rigid_plane_coarse.prm
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_consistent_coarse.prm
    ${_work}/rigid_obstacle)
set_tests_properties(rigid_obstacle_reduction PROPERTIES TIMEOUT 900)

# Issue 4: IGA with HRZ mass at the benchmark level (1024 knot spans per
# half cylinder, about 15 s) against the analytic reference.
add_test(NAME hertz_iga_hrz_benchmark
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/hertz_benchmark.py
    $<TARGET_FILE:isoimpact_program>
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_level4.prm ${_work})
set_tests_properties(hertz_iga_hrz_benchmark PROPERTIES TIMEOUT 600)

# Issue 4: FEA and IGA (HRZ) refined 2, 3 and 4 times converge together.
add_test(NAME fea_iga_refinement
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/fea_iga_refinement.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_SOURCE_DIR}
    ${_work}/fea_iga_refinement)
set_tests_properties(fea_iga_refinement PROPERTIES TIMEOUT 900)

# The study's FEA element (Q8 serendipity) with HRZ mass on the test mesh.
add_test(NAME hertz_fea_q8_hrz_benchmark
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/hertz_benchmark.py
    $<TARGET_FILE:isoimpact_program>
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_q8_hrz_coarse.prm ${_work})
set_tests_properties(hertz_fea_q8_hrz_benchmark PROPERTIES TIMEOUT 600)

# The layering (doc/architecture.md) from the #include lines: a file of layer
# k includes no header of a layer above k; and the check fails, naming the
# file, once a wrong-way include is added to a copy of the tree.
add_test(NAME layering
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/check_layering.py ${CMAKE_SOURCE_DIR})
add_test(NAME layering_check_can_fail
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/check_layering.py --self-test
    ${CMAKE_SOURCE_DIR})

# The contact damping remedy (issue 11) on the coarse meshes: chatter,
# consistent pressure, energy balance with the damping's work, stable step.
add_test(NAME contact_damping
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/contact_damping.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_CURRENT_SOURCE_DIR}/prm
    ${_work}/contact_damping)
set_tests_properties(contact_damping PROPERTIES TIMEOUT 900)

# The bipenalty (issue 11) on the coarse meshes: stable step, energy balance
# with the mass penalty's terms, force trend peak, refused combinations.
add_test(NAME bipenalty
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/bipenalty.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_CURRENT_SOURCE_DIR}/prm
    ${_work}/bipenalty)
set_tests_properties(bipenalty PROPERTIES TIMEOUT 900)

# Output that survives a stop, a full disk and a rerun (issue 10).
add_test(NAME output_robustness
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/output_robustness.py
    $<TARGET_FILE:isoimpact_program>
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm ${_work}/output_robustness)
set_tests_properties(output_robustness PROPERTIES TIMEOUT 300)

# Contact/Penalty = auto (issue 11) on the coarse meshes.
add_test(NAME penalty_auto
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/penalty_auto.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_CURRENT_SOURCE_DIR}/prm
    ${_work}/penalty_auto)
set_tests_properties(penalty_auto PROPERTIES TIMEOUT 600)

# The coarse trade-off sweep (issue 12): errors fall with cost.
add_test(NAME tradeoff_front
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/tradeoff_front.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_SOURCE_DIR}/scripts/tradeoff_study.py
    ${_work}/tradeoff_front)
set_tests_properties(tradeoff_front PROPERTIES TIMEOUT 600)

# The mass redistribution remedy (issue 11) on the coarse meshes, FEA and
# IGA: chatter, force trend peak, energy balance, stable step, solve work.
add_test(NAME mass_redistribution_remedy
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/mass_redistribution_remedy.py
    $<TARGET_FILE:isoimpact_program> ${CMAKE_CURRENT_SOURCE_DIR}/prm
    ${_work}/mass_redistribution_remedy)
set_tests_properties(mass_redistribution_remedy PROPERTIES TIMEOUT 900)

# The distribution of the unknowns over 2 MPI ranks and the distributed
# stiffness product (issue 13's first step); the same program runs above as
# one process.
find_program(ISOIMPACT_MPIRUN mpirun)
if(NOT ISOIMPACT_MPIRUN)
  message(FATAL_ERROR "mpirun not found (Debian: apt-get install openmpi-bin)")
endif()
add_test(NAME unknown_partition_2_ranks
  COMMAND ${ISOIMPACT_MPIRUN} --allow-run-as-root --oversubscribe -np 2
    $<TARGET_FILE:test_unknown_partition>)
set_tests_properties(unknown_partition_2_ranks PROPERTIES TIMEOUT 300)

# The consistent mass's solve split over 2 MPI ranks by the subtrees of its
# elimination tree: the checks of consistent_mass_solve on the ranks, and
# the split solve against one process's (one thread per rank: the same two
# groups of subtrees, the same bits).
add_test(NAME consistent_mass_solve_2_ranks
  COMMAND ${ISOIMPACT_MPIRUN} --allow-run-as-root --oversubscribe -np 2
    -x DEAL_II_NUM_THREADS=1 $<TARGET_FILE:test_consistent_mass_solve>)
set_tests_properties(consistent_mass_solve_2_ranks PROPERTIES TIMEOUT 600)

# The program on 2 MPI ranks against one process (issue 13), FEA Q9 and Q8,
# IGA, HRZ, row-sum and consistent, two bodies and a rigid plane, contact
# damping, the bipenalty, mass redistribution (FEA and IGA), local
# refinement (FEA's hanging nodes, IGA's knot insertion): the
# first 200 steps of the history to 1e-10, impulse, duration and force peaks
# to 1e-4, energies and masses; the ParaView pieces of the ranks (subdivided
# FEA, higher-order IGA cells) join to the serial output. One case runs on 3
# ranks (IGA consistent: the third rank has no subtree of the mass's factor).
# Two bodies of equal size with a lumped mass go whole to a rank each
# (Parallel/Distribution = automatic); the split cases divide every body
# between the ranks. Load balancing (2 ranks, lumped mass) is automatic by
# default: the ranks of a test are on one node, so bodies whole on ranks
# hold their state in memory both ranks map (shared memory, sessions
# 40-41), and split bodies are measured. One case asks for measured with
# whole FEA bodies and ParaView records; three ask for shared memory with
# split bodies: FEA with ParaView records, IGA with contact damping, a rigid
# plane with the history every 7th step.
# The sweep cases move the rows near the ranks' interface (split)
# or the layers of a body farthest from its contact surface (whole bodies)
# every step; one whole-body case keeps the bodies whole (off). Ranks with a
# lumped mass need not meet at every step (session 34): cases write the
# history at every 7th and 5th step, so that the energies are summed one
# step late in between, and one on 3 ranks. Four cases share the band
# within each step (Load balancing = claimed, session 38): whole bodies with
# ParaView records, the history every 7th step, split bodies with contact
# damping, and a rigid plane. Two cases exchange the contact's outcomes in
# messages (MPI_Allgather, Parallel/Contact point exchange = messages), the
# path of ranks on different nodes: whole bodies in shared memory, and the
# consistent mass on 3 ranks.
add_test(NAME mpi_history_2_ranks
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/mpi_history.py
    $<TARGET_FILE:isoimpact_program> ${ISOIMPACT_MPIRUN} ${_work}/mpi_history
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Output/VTU interval=600"
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_rigid_plane_coarse.prm
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_q8_hrz_coarse.prm@Parallel/Distribution=split@Parallel/Load balancing=off"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Parallel/Distribution=split"
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_rowsum_coarse.prm
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Parallel/Load balancing=sweep@Output/VTU interval=301"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Parallel/Load balancing=sweep@Contact/Damping ratio=0.2"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_q8_hrz_coarse.prm@Parallel/Load balancing=off"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Parallel/Distribution=split@Parallel/Load balancing=sweep@Output/VTU interval=301"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Parallel/Distribution=split@Parallel/Load balancing=sweep@Contact/Damping ratio=0.2"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_rigid_plane_coarse.prm@Parallel/Distribution=split@Parallel/Load balancing=sweep"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Contact/Damping ratio=0.2"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Discretization/Local refinements=1@Time integration/Time step=0.00025"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Discretization/Local refinements=1@Time integration/Time step=0.00025"
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_consistent_coarse.prm
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Mass matrix/Scheme=consistent"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Contact/Bipenalty=true"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Contact/Mass redistribution=true"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Contact/Mass redistribution=true"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_consistent_coarse.prm@Output/VTU interval=600@ranks=3"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Output/History interval=7"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Parallel/Distribution=split@Output/History interval=5"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@ranks=3@Output/History interval=3"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Parallel/Load balancing=claimed@Output/VTU interval=301"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Parallel/Load balancing=claimed@Output/History interval=7"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Parallel/Distribution=split@Parallel/Load balancing=claimed@Contact/Damping ratio=0.2"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_rigid_plane_coarse.prm@Parallel/Load balancing=claimed"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Parallel/Load balancing=measured@Output/VTU interval=301"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Parallel/Distribution=split@Parallel/Load balancing=shared memory@Output/VTU interval=301"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Parallel/Distribution=split@Parallel/Load balancing=shared memory@Contact/Damping ratio=0.2"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_rigid_plane_coarse.prm@Parallel/Load balancing=shared memory@Output/History interval=7"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Parallel/Contact point exchange=messages"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Mass matrix/Scheme=consistent@Parallel/Contact point exchange=messages@ranks=3")
set_tests_properties(mpi_history_2_ranks PROPERTIES TIMEOUT 600)

# One thread against two (one process): on two threads the bodies' steps run
# side by side as tasks, and the lumped pass, the energies and the
# consistent mass's substitutions are split over the threads; the history
# must be the same to the last bit. FEA and IGA, HRZ and consistent, a rigid
# plane (one body), contact damping, the bipenalty, mass redistribution, and
# each body's pass on one thread (Parallel/Thread partition = by body).
add_test(NAME thread_history
  COMMAND ${ISOIMPACT_PYTHON} ${_scripts}/thread_history.py
    $<TARGET_FILE:isoimpact_program> ${_work}/thread_history
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_consistent_coarse.prm
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Mass matrix/Scheme=consistent"
    ${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_rigid_plane_coarse.prm
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Contact/Damping ratio=0.2"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Contact/Bipenalty=true"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_fea_hrz_coarse.prm@Contact/Mass redistribution=true"
    "${CMAKE_CURRENT_SOURCE_DIR}/prm/hertz_iga_hrz_coarse.prm@Parallel/Thread partition=by body")
set_tests_properties(thread_history PROPERTIES TIMEOUT 600)
