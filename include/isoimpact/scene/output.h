// Layer 6: ParaView output of the bodies (VTU per body, PVTU per time,
// one PVD for the run) with displacement, velocity and stresses.
#ifndef isoimpact_output_h
#define isoimpact_output_h

#include <isoimpact/mechanics/elastic_body.h>

#include <string>
#include <utility>
#include <vector>

namespace isoimpact
{
  class SolutionWriter
  {
  public:
    SolutionWriter(const std::string &directory,
                   const unsigned int n_subdivisions);

    // Writes body<i>_<NNNN>.vtu for each body, solution_<NNNN>.pvtu and
    // rewrites solution.pvd. Returns the name of the .pvtu file.
    std::string
    write(const std::vector<ElasticBody<2> *> &bodies, const double time);

  private:
    std::string                                 directory;
    unsigned int                                n_subdivisions;
    unsigned int                                counter = 0;
    std::vector<std::pair<double, std::string>> times_and_names;
  };
} // namespace isoimpact

#endif
