// Layer 6: ParaView output, history and pressure profiles.
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <isoimpact/scene/output.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    // Stresses (Pa) from the displacement gradient: the in-plane components,
    // sigma_zz and the von Mises stress.
    class StressPostprocessor : public DataPostprocessor<2>
    {
    public:
      explicit StressPostprocessor(const ElasticMaterial &material)
        : material(material)
      {}

      void
      evaluate_vector_field(
        const DataPostprocessorInputs::Vector<2> &inputs,
        std::vector<Vector<double>> &computed_quantities) const override
      {
        for (unsigned int q = 0; q < inputs.solution_gradients.size(); ++q)
          {
            SymmetricTensor<2, 2> strain;
            for (unsigned int i = 0; i < 2; ++i)
              for (unsigned int j = i; j < 2; ++j)
                strain[i][j] = 0.5 * (inputs.solution_gradients[q][i][j] +
                                      inputs.solution_gradients[q][j][i]);
            const auto   sigma     = material.stress(strain);
            const double sigma_zz  = material.out_of_plane_stress(strain);
            const double von_mises = std::sqrt(
              0.5 * ((sigma[0][0] - sigma[1][1]) * (sigma[0][0] - sigma[1][1]) +
                     (sigma[1][1] - sigma_zz) * (sigma[1][1] - sigma_zz) +
                     (sigma_zz - sigma[0][0]) * (sigma_zz - sigma[0][0])) +
              3. * sigma[0][1] * sigma[0][1]);
            computed_quantities[q](0) = sigma[0][0];
            computed_quantities[q](1) = sigma[1][1];
            computed_quantities[q](2) = sigma[0][1];
            computed_quantities[q](3) = sigma_zz;
            computed_quantities[q](4) = von_mises;
          }
      }

      std::vector<std::string>
      get_names() const override
      {
        return {"stress_xx_Pa",
                "stress_yy_Pa",
                "stress_xy_Pa",
                "stress_zz_Pa",
                "von_mises_stress_Pa"};
      }

      UpdateFlags
      get_needed_update_flags() const override
      {
        return update_gradients;
      }

    private:
      const ElasticMaterial material;
    };
  } // namespace



  void
  close_and_check(std::ofstream     &out,
                  const std::string &path,
                  const std::string &name)
  {
    out.close();
    if (out.fail())
      {
        const std::string reason = std::strerror(errno);
        std::error_code   ignored; // a half-written file is not left
        std::filesystem::remove(path, ignored);
        throw std::runtime_error("writing '" + (name.empty() ? path : name) +
                                 "' failed: " + reason +
                                 " (is the disk full?)");
      }
  }



  void
  write_by_rename(const std::string                         &path,
                  const std::function<void(std::ostream &)> &writer)
  {
    const std::string temporary = path + ".tmp";
    {
      std::ofstream out(temporary);
      writer(out);
      close_and_check(out, temporary, path);
    }
    std::filesystem::rename(temporary, path);
  }



  SolutionWriter::SolutionWriter(const std::string &directory,
                                 const unsigned int n_subdivisions)
    : directory(directory)
    , n_subdivisions(n_subdivisions)
  {}

  std::string
  SolutionWriter::write(const std::vector<ElasticBody<2> *> &bodies,
                        const double                         time)
  {
    const std::string        number = Utilities::int_to_string(counter++, 4);
    std::vector<std::string> pieces;
    for (const auto *body : bodies)
      {
        const auto    &disc = body->discretization();
        Vector<double> displacement(disc.dof_handler().n_dofs());
        Vector<double> velocity(disc.dof_handler().n_dofs());
        disc.to_dof_handler_vector(body->displacement, displacement);
        disc.to_dof_handler_vector(body->velocity, velocity);

        const std::vector<
          DataComponentInterpretation::DataComponentInterpretation>
          vector_field(
            2,
            DataComponentInterpretation::component_is_part_of_vector);
        StressPostprocessor stresses(body->material());
        DataOut<2>          data_out;
        data_out.attach_dof_handler(disc.dof_handler());
        data_out.add_data_vector(displacement,
                                 std::vector<std::string>(2, "displacement_m"),
                                 DataOut<2>::type_dof_data,
                                 vector_field);
        data_out.add_data_vector(velocity,
                                 std::vector<std::string>(2,
                                                          "velocity_m_per_s"),
                                 DataOut<2>::type_dof_data,
                                 vector_field);
        data_out.add_data_vector(displacement, stresses);
        data_out.build_patches(disc.mapping(),
                               n_subdivisions,
                               DataOut<2>::curved_inner_cells);
        DataOutBase::VtkFlags flags(time);
        data_out.set_flags(flags);

        const std::string piece = body->name() + "_" + number + ".vtu";
        // Every file by rename: a stopped run leaves complete files (and
        // at most one .tmp).
        write_by_rename(directory + "/" + piece, [&](std::ostream &out) {
          try
            {
              data_out.write_vtu(out);
            }
          catch (const ExceptionBase &)
            {
              out.setstate(std::ios::badbit); // reported by close_and_check
            }
        });
        pieces.push_back(piece);
        if (body == bodies.back())
          {
            const std::string pvtu = "solution_" + number + ".pvtu";
            write_by_rename(directory + "/" + pvtu, [&](std::ostream &record) {
              try
                {
                  data_out.write_pvtu_record(record, pieces);
                }
              catch (const ExceptionBase &)
                {
                  record.setstate(std::ios::badbit);
                }
            });
            times_and_names.emplace_back(time, pvtu);
          }
      }
    // Rewritten at every output: by rename, so that a stop leaves the
    // previous complete record.
    write_by_rename(directory + "/solution.pvd", [&](std::ostream &pvd) {
      try
        {
          DataOutBase::write_pvd_record(pvd, times_and_names);
        }
      catch (const ExceptionBase &)
        {
          pvd.setstate(std::ios::badbit);
        }
    });
    return times_and_names.back().second;
  }



  HistoryWriter::HistoryWriter(const std::string &path,
                               const std::string &parameter_file,
                               const Parameters  &parameters,
                               const Scene       &scene)
    : scene(scene)
    , path(path)
    , out(path)
  {
    out << "# isoimpact history of " << parameter_file << "\n"
        << "# units: time [s], contact_force [N/m] (resultant on body 1 "
           "along the line of impact, per unit thickness, full bodies), "
           "max_contact_pressure [Pa] (maximum of the consistent pressure "
           "field), max_gauss_point_pressure [Pa] (maximum of the "
           "pointwise penalty traction), energies [J/m] (per unit "
           "thickness, full bodies; contact_damping_work: the work the "
           "contact damping removed since t = 0, included in "
           "total_energy), analytic columns: quasi-static "
           "Hertz impact ("
        << parameters.approach_law << ")\n";
    if (parameters.obstacle.active())
      out << "# scene: body 1 against a " << scene.contacts[0]->description()
          << "; energies are those of body 1 (the obstacle stores none)\n";
    if (scene.symmetry_factor != 1.)
      out << "# the model is a half by symmetry: contact_force and "
             "energies are those of the model times "
          << scene.symmetry_factor << "\n";
    out << "time,contact_force,max_contact_pressure,max_gauss_point_pressure,"
           "kinetic_energy,"
           "strain_energy,contact_energy,contact_damping_work,total_energy";
    if (scene.reference)
      out << ",analytic_contact_force,analytic_max_contact_pressure";
    out << '\n';
    rows << std::setprecision(10);
    flush();
  }



  HistoryWriter::~HistoryWriter()
  {
    try
      {
        flush();
      }
    catch (...)
      {}
  }



  void
  HistoryWriter::flush()
  {
    out << rows.str();
    out.flush();
    rows.str("");
    if (!out)
      {
        // Cut back to the last complete row: the file stays readable.
        const std::string reason = std::strerror(errno);
        std::error_code   ignored;
        std::filesystem::resize_file(path, written, ignored);
        throw std::runtime_error("writing '" + path + "' failed: " + reason +
                                 " (is the disk full?)");
      }
    written = out.tellp();
  }



  void
  HistoryWriter::write(const double         time,
                       const double         contact_force,
                       const double         max_pressure,
                       const double         max_gauss_point_pressure,
                       const EnergyBalance &energy)
  {
    const double factor = scene.symmetry_factor;
    rows << time << ',' << contact_force << ',' << max_pressure << ','
         << max_gauss_point_pressure << ',' << factor * energy.kinetic << ','
         << factor * energy.strain << ',' << factor * energy.contact << ','
         << factor * energy.contact_damping << ',' << factor * energy.total();
    if (scene.reference)
      rows << ',' << scene.reference->contact_force(time) << ','
           << scene.reference->max_contact_pressure(time);
    rows << '\n';
    // Whole rows only reach the file: a killed run leaves complete ones.
    if (rows.tellp() > (1 << 16))
      flush();
  }



  void
  write_pressure_profile(const std::string                &directory,
                         const double                      time,
                         std::vector<ContactPoint<2>>      points,
                         const Tensor<1, 2>               &impact_direction,
                         const HertzImpactReference *const reference)
  {
    Tensor<1, 2> across;
    across[0] = impact_direction[1];
    across[1] = -impact_direction[0];
    std::sort(points.begin(), points.end(), [&](const auto &a, const auto &b) {
      return a.reference_position * across < b.reference_position * across;
    });

    std::ostringstream name;
    name << directory << "/contact_pressure_t" << std::fixed
         << std::setprecision(4) << time << ".csv";
    write_by_rename(name.str(), [&](std::ostream &out) {
      out << "# contact pressure along the contact surface at t = " << time
          << " s\n# units: position [m] (reference position across the line "
             "of impact), pressure [Pa] (the consistent pressure field), "
             "gauss_point_pressure [Pa] (the pointwise penalty traction); "
             "surface: 1 or 2 (the body whose Gauss point it is)\n"
             "position,pressure,gauss_point_pressure,surface";
      const double force = reference ? reference->contact_force(time) : 0.;
      if (reference)
        out << ",analytic_pressure";
      out << '\n' << std::setprecision(10);
      for (const auto &point : points)
        {
          const double s = point.reference_position * across;
          out << s << ',' << point.pressure << ',' << point.gauss_point_pressure
              << ',' << point.body + 1;
          if (reference)
            out << ',' << reference->pressure(force, s);
          out << '\n';
        }
    });
  }
} // namespace isoimpact
