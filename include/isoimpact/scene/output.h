// Layer 6: the output files of a run: ParaView output of the bodies (VTU per
// body, PVTU per time, one PVD for the run) with displacement, velocity and
// stresses; the history of the contact force, pressure and energies; the
// pressure profiles along the contact surface.
#ifndef isoimpact_output_h
#define isoimpact_output_h

#include <isoimpact/mechanics/elastic_body.h>
#include <isoimpact/scene/parameters.h>
#include <isoimpact/scene/scene.h>

#include <cstdint>
#include <fstream>
#include <functional>
#include <future>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace isoimpact
{
  // Closes a written file; if any write failed (a full disk) removes it and
  // throws std::runtime_error naming it (or `name`, if given).
  void
  close_and_check(std::ofstream     &out,
                  const std::string &path,
                  const std::string &name = "");

  // Writes a file under path.tmp and renames it to path, so that the file
  // is always either the old or the new complete one.
  void
  write_by_rename(const std::string                         &path,
                  const std::function<void(std::ostream &)> &writer);

  class SolutionWriter
  {
  public:
    // higher_order: one higher-order VTK cell per element
    // (Discretization::higher_order_cell()), its arrays raw or (compress)
    // zlib-compressed in the appended section; else deal.II's DataOut with
    // n_subdivisions^2 linear cells per element.
    SolutionWriter(const std::string &directory,
                   const unsigned int n_subdivisions,
                   const bool         higher_order,
                   const bool         compress = false);

    // Writes body<i>_<NNNN>.vtu for each body, solution_<NNNN>.pvtu and
    // rewrites solution.pvd. Returns the name of the .pvtu file. On several
    // MPI ranks every rank calls it with the whole state (gather_state())
    // and writes the pieces of its own cells, body<i>_<NNNN>.<rank>.vtu;
    // rank 0 writes the records, which list every rank's pieces.
    // `contact_pressures` (per body, see contact_pressure_nodal_values())
    // gives the point field contact_pressure_Pa: on the contact surface it
    // is the consistent contact pressure (the interior functions vanish
    // there); inside the body it has no meaning.
    // With higher-order cells the fields are sampled before write()
    // returns and the files are compressed and written by a background
    // task (one at a time); finish() waits for it and throws if a write
    // failed.
    std::string
    write(const std::vector<ElasticBody<2> *>       &bodies,
          const double                               time,
          const std::vector<dealii::Vector<double>> &contact_pressures);

    // Waits for the files of the last write(); rethrows its error.
    void
    finish();

    // Waits for a write in flight (without reporting its error).
    ~SolutionWriter();

    // Shape data of a body's cells at the VTK node points (output.cc).
    struct BodySampling;

  private:
    // Per body, made at its first higher-order write.
    std::vector<std::shared_ptr<BodySampling>>  samplings;
    std::future<void>                           pending;
    std::string                                 directory;
    unsigned int                                n_subdivisions;
    bool                                        higher_order;
    bool                                        compress;
    unsigned int                                counter = 0;
    std::vector<std::pair<double, std::string>> times_and_names;
  };

  /**
   * Per body of the scene: the nodal values p_k (Pa) of the consistent
   * contact pressure (SurfaceNodes::project_pressure) on the x unknowns of
   * the contact surface nodes, 0 elsewhere, from contact results evaluated
   * with record_points (ContactResult::nodal_pressures), one per
   * interaction of the scene.
   */
  std::vector<dealii::Vector<double>>
  contact_pressure_nodal_values(const Scene                         &scene,
                                const std::vector<ContactResult<2>> &results);

  /**
   * history.csv: a header that says the unit of every column, then one row
   * per call of write(). Contact force and energies are those of the full
   * bodies (the model's times the scene's symmetry factor); with an analytic
   * reference, its force and maximal pressure follow. Rows reach the file
   * whole, at flush() (the program calls it at each progress line) and
   * every 64 kB, so a killed run leaves only complete rows; a failed write
   * throws std::runtime_error.
   */
  class HistoryWriter
  {
  public:
    HistoryWriter(const std::string &path,
                  const std::string &parameter_file,
                  const Parameters  &parameters,
                  const Scene       &scene);
    ~HistoryWriter();

    void
    flush();

    // The contact force and pressure as reported (full bodies); the
    // energies of the model.
    void
    write(const double         time,
          const double         contact_force,
          const double         max_pressure,
          const double         max_gauss_point_pressure,
          const EnergyBalance &energy,
          const unsigned int   boundary_solve_work = 0);

  private:
    // Contact/Mass redistribution: the column boundary_solve_work.
    bool              with_boundary_solve = false;
    const Scene      &scene;
    const std::string path;
    std::ofstream     out;
    std::string       rows;        // complete rows not yet in the file
    std::uintmax_t    written = 0; // bytes of complete rows in the file
    // Contact/Bipenalty: two more energy columns.
    bool bipenalty = false;
  };

  /**
   * contact_pressure_t<time>.csv in the directory: one row per contact
   * point, sorted by its reference position across the line of impact,
   * with the body whose point it is and, with a reference, the Hertz
   * profile of the analytic force at that time.
   */
  void
  write_pressure_profile(const std::string                &directory,
                         const double                      time,
                         std::vector<ContactPoint<2>>      points,
                         const dealii::Tensor<1, 2>       &impact_direction,
                         const HertzImpactReference *const reference);
} // namespace isoimpact

#endif
