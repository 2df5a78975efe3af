// Layer 6: ParaView output, history and pressure profiles.
#include <deal.II/base/quadrature.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/filtered_iterator.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <isoimpact/scene/output.h>

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <type_traits>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    const std::vector<std::string> stress_names = {"stress_xx_Pa",
                                                   "stress_yy_Pa",
                                                   "stress_xy_Pa",
                                                   "stress_zz_Pa",
                                                   "von_mises_stress_Pa"};

    // The in-plane stresses, sigma_zz and the von Mises stress (Pa) from a
    // displacement gradient, in the order of stress_names.
    std::array<double, 5>
    stresses(const ElasticMaterial &material, const Tensor<2, 2> &gradient)
    {
      SymmetricTensor<2, 2> strain;
      for (unsigned int i = 0; i < 2; ++i)
        for (unsigned int j = i; j < 2; ++j)
          strain[i][j] = 0.5 * (gradient[i][j] + gradient[j][i]);
      const auto   sigma     = material.stress(strain);
      const double sigma_zz  = material.out_of_plane_stress(strain);
      const double von_mises = std::sqrt(
        0.5 * ((sigma[0][0] - sigma[1][1]) * (sigma[0][0] - sigma[1][1]) +
               (sigma[1][1] - sigma_zz) * (sigma[1][1] - sigma_zz) +
               (sigma_zz - sigma[0][0]) * (sigma_zz - sigma[0][0])) +
        3. * sigma[0][1] * sigma[0][1]);
      return {{sigma[0][0], sigma[1][1], sigma[0][1], sigma_zz, von_mises}};
    }

    // The stresses for deal.II's DataOut (subdivided cells).
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
            Tensor<2, 2> gradient;
            for (unsigned int i = 0; i < 2; ++i)
              gradient[i] = inputs.solution_gradients[q][i];
            const auto values = stresses(material, gradient);
            for (unsigned int k = 0; k < values.size(); ++k)
              computed_quantities[q](k) = values[k];
          }
      }

      std::vector<std::string>
      get_names() const override
      {
        return stress_names;
      }

      UpdateFlags
      get_needed_update_flags() const override
      {
        return update_gradients;
      }

    private:
      const ElasticMaterial material;
    };

    // Component 0 of a vector field as contact_pressure_Pa (DataOut).
    class PressurePostprocessor : public DataPostprocessorScalar<2>
    {
    public:
      PressurePostprocessor()
        : DataPostprocessorScalar<2>("contact_pressure_Pa", update_values)
      {}

      void
      evaluate_vector_field(
        const DataPostprocessorInputs::Vector<2> &inputs,
        std::vector<Vector<double>> &computed_quantities) const override
      {
        for (unsigned int q = 0; q < inputs.solution_values.size(); ++q)
          computed_quantities[q](0) = inputs.solution_values[q](0);
      }
    };

    // The data arrays of a VTK XML file in its appended section (raw
    // binary: no base64, which took as long as the compression). Each block
    // is a UInt64 header and the bytes; with zlib, the header of VTK's
    // vtkZLibDataCompressor (one block) and zlib's fastest level. Without
    // compression the arrays are not copied: add() keeps a pointer, and the
    // data must live until write().
    class AppendedArrays
    {
    public:
      explicit AppendedArrays(const bool compress)
        : compress(compress)
      {}

      // Appends the data; returns its <DataArray/> element.
      template <typename T>
      std::string
      add(const std::string    &name,
          const unsigned int    n_components,
          const std::vector<T> &data)
      {
        const char        *type = std::is_same_v<T, double>       ? "Float64" :
                                  std::is_same_v<T, std::uint8_t> ? "UInt8" :
                                                                    "Int64";
        std::ostringstream element;
        element << "<DataArray type=\"" << type << '"';
        if (!name.empty())
          element << " Name=\"" << name << '"';
        element << " NumberOfComponents=\"" << n_components
                << "\" format=\"appended\" offset=\"" << offset << "\"/>\n";
        const std::uint64_t size  = data.size() * sizeof(T);
        const auto         *begin = reinterpret_cast<const char *>(data.data());
        Block               block;
        if (!compress)
          {
            block.header         = {{size}};
            block.n_header_words = 1;
            block.data           = begin;
            block.size           = size;
          }
        else
          {
            uLongf compressed_size = compressBound(size);
            block.compressed.resize(compressed_size);
            const int status =
              compress2(reinterpret_cast<Bytef *>(block.compressed.data()),
                        &compressed_size,
                        reinterpret_cast<const Bytef *>(begin),
                        size,
                        Z_BEST_SPEED);
            AssertThrow(status == Z_OK, ExcMessage("zlib compression failed"));
            // blocks, block size, size of the last block, compressed sizes
            block.header         = {{1, size, size, compressed_size}};
            block.n_header_words = 4;
            block.data           = block.compressed.data();
            block.size           = compressed_size;
          }
        offset += block.n_header_words * sizeof(std::uint64_t) + block.size;
        blocks.push_back(std::move(block));
        return element.str();
      }

      // The attributes of <VTKFile> that describe the arrays.
      std::string
      file_attributes() const
      {
        return std::string("byte_order=\"LittleEndian\" "
                           "header_type=\"UInt64\"") +
               (compress ? " compressor=\"vtkZLibDataCompressor\"" : "");
      }

      void
      write(std::ostream &out) const
      {
        out << "<AppendedData encoding=\"raw\">\n_";
        for (const auto &block : blocks)
          {
            out.write(reinterpret_cast<const char *>(block.header.data()),
                      block.n_header_words * sizeof(std::uint64_t));
            out.write(block.data, block.size);
          }
        out << "\n</AppendedData>\n";
      }

    private:
      struct Block
      {
        std::array<std::uint64_t, 4> header         = {};
        unsigned int                 n_header_words = 0;
        const char                  *data           = nullptr;
        std::uint64_t                size           = 0;
        std::vector<char>            compressed;
      };

      const bool         compress;
      std::uint64_t      offset = 0;
      std::vector<Block> blocks;
    };

    // The point arrays (name, components) of both writers; the higher-order
    // cells add the rational weights.
    std::vector<std::pair<std::string, unsigned int>>
    point_arrays(const bool higher_order)
    {
      std::vector<std::pair<std::string, unsigned int>> arrays =
        {{"displacement_m", 3}, {"velocity_m_per_s", 3}};
      for (const auto &name : stress_names)
        arrays.emplace_back(name, 1);
      arrays.emplace_back("contact_pressure_Pa", 1);
      if (higher_order)
        arrays.emplace_back("RationalWeights", 1);
      return arrays;
    }

    // Displacement, velocity and the contact pressure of a body on its
    // DoFHandler.
    struct DoFFields
    {
      DoFFields(const ElasticBody<2> &body,
                const Vector<double> &contact_pressure)
      {
        const auto &disc = body.discretization();
        const std::array<const Vector<double> *, 3> unknowns = {
          {&body.displacement, &body.velocity, &contact_pressure}};
        for (unsigned int i = 0; i < 3; ++i)
          disc.to_dof_handler_vector(*unknowns[i], vectors[i]);
      }
      std::array<Vector<double>, 3> vectors;
    };

    // One body with deal.II's DataOut: n_subdivisions^2 linear cells per
    // element. Compressed with zlib's fastest level: the default (best
    // compression) took most of the run's time.
    // With empty_piece, no cell: the arrays of `body` without values (the
    // piece of a body whose cells this rank does not hold).
    void
    write_subdivided_vtu(std::ostream         &out,
                         const ElasticBody<2> &body,
                         const Vector<double> &contact_pressure,
                         const double          time,
                         const unsigned int    n_subdivisions,
                         const bool            empty_piece = false)
    {
      const auto     &disc = body.discretization();
      const DoFFields fields(body, contact_pressure);
      const auto &[displacement, velocity, pressure] = fields.vectors;

      const std::vector<
        DataComponentInterpretation::DataComponentInterpretation>
                          vector_field(2,
                     DataComponentInterpretation::component_is_part_of_vector);
      StressPostprocessor stress_fields(body.material());
      DataOut<2>          data_out;
      data_out.attach_dof_handler(disc.dof_handler());
      data_out.add_data_vector(displacement,
                               std::vector<std::string>(2, "displacement_m"),
                               DataOut<2>::type_dof_data,
                               vector_field);
      data_out.add_data_vector(velocity,
                               std::vector<std::string>(2, "velocity_m_per_s"),
                               DataOut<2>::type_dof_data,
                               vector_field);
      data_out.add_data_vector(displacement, stress_fields);
      PressurePostprocessor pressure_field;
      data_out.add_data_vector(pressure, pressure_field);
      // Several MPI ranks: this rank's cells (UnknownExchange::owns_cell).
      const UnknownExchange &exchange = body.exchange();
      if (exchange.is_distributed() || empty_piece)
        data_out.set_cell_selection(FilteredIterator<DataOut<2>::cell_iterator>(
          [&exchange, empty_piece](const DataOut<2>::cell_iterator &cell) {
            return !empty_piece && cell->is_active() &&
                   exchange.owns_cell(cell->active_cell_index());
          }));
      data_out.build_patches(disc.mapping(),
                             n_subdivisions,
                             DataOut<2>::curved_inner_cells);
      DataOutBase::VtkFlags flags(time);
      flags.compression_level = DataOutBase::VtkFlags::best_speed;
      data_out.set_flags(flags);
      data_out.write_vtu(out);
    }

    // The fields of one body sampled as higher-order VTK cells: all a VTU
    // file holds, independent of the body's later state, so that it can be
    // compressed and written while the time loop goes on.
    struct HigherOrderPiece
    {
      double                           time     = 0.;
      unsigned int                     degree   = 0;
      unsigned int                     vtk_type = 0;
      unsigned int                     n_cells  = 0;
      std::vector<double>              points;
      std::vector<std::vector<double>> point_data;
    };

    // The shape functions of one cell at its VTK node points. The element
    // is a vector-valued FESystem of one scalar element: its values and
    // gradients are stored per function of that element (half the bytes of
    // one per vector-valued function), with the node coefficients of the
    // position.
    template <typename Number>
    struct CellShapesOf
    {
      Number *position_coefficients; // n x 2
      Number *values;                // n x scalar functions
      Number *gradients;             // n x scalar functions x 2
    };
    using CellShapes       = CellShapesOf<const double>;
    using CellShapesToFill = CellShapesOf<double>;

    void
    fill_cell_shapes(FEValues<2>                               &fe_values,
                     const Discretization<2>                   &disc,
                     const DoFHandler<2>::active_cell_iterator &cell,
                     HigherOrderCell                           &vtk_cell,
                     const CellShapesToFill                    &shapes)
    {
      vtk_cell = disc.higher_order_cell(cell);
      fe_values.reinit(cell);
      const auto        &fe = fe_values.get_fe();
      const unsigned int n  = fe_values.n_quadrature_points;
      const unsigned int m  = fe.n_dofs_per_cell();
      const unsigned int mb = fe.base_element(0).n_dofs_per_cell();
      if (vtk_cell.values_to_nodes.m() > 0)
        {
          FullMatrix<double> positions(n, 2), coefficients(n, 2);
          for (unsigned int k = 0; k < n; ++k)
            for (unsigned int d = 0; d < 2; ++d)
              positions(k, d) = fe_values.quadrature_point(k)[d];
          vtk_cell.values_to_nodes.mmult(coefficients, positions);
          for (unsigned int k = 0; k < n; ++k)
            for (unsigned int d = 0; d < 2; ++d)
              shapes.position_coefficients[2 * k + d] = coefficients(k, d);
        }
      else
        for (unsigned int k = 0; k < n; ++k)
          for (unsigned int d = 0; d < 2; ++d)
            shapes.position_coefficients[2 * k + d] =
              fe_values.quadrature_point(k)[d];
      // The functions of component 0 are those of the scalar element.
      for (unsigned int i = 0; i < m; ++i)
        {
          const auto [c, j] = fe.system_to_component_index(i);
          if (c != 0)
            continue;
          for (unsigned int k = 0; k < n; ++k)
            {
              shapes.values[k * mb + j] =
                fe_values.shape_value_component(i, k, 0);
              const auto gradient = fe_values.shape_grad_component(i, k, 0);
              shapes.gradients[2 * (k * mb + j)]     = gradient[0];
              shapes.gradients[2 * (k * mb + j) + 1] = gradient[1];
            }
        }
    }

    std::unique_ptr<FEValues<2>>
    node_fe_values(const Discretization<2> &disc, const unsigned int degree)
    {
      const auto nodes = vtk_node_points(degree);
      return std::make_unique<FEValues<2>>(
        disc.mapping(),
        disc.fe(),
        Quadrature<2>(nodes, std::vector<double>(nodes.size(), 1.)),
        update_values | update_gradients | update_quadrature_points);
    }
  } // namespace

  // Kept from one write to the next, the shape data make a write cost a
  // few products per node instead of a mapping per cell; bodies whose
  // data would exceed max_cached_bytes are sampled through FEValues at
  // every write instead. The sampled pieces are kept too, two of them
  // (a write fills one while the previous one is being written): a write
  // reuses their memory instead of taking fresh pages.
  struct SolutionWriter::BodySampling
  {
    static constexpr std::size_t max_cached_bytes = std::size_t(64) << 20;

    explicit BodySampling(const Discretization<2> &disc)
    {
      const auto &fe = disc.fe();
      AssertThrow(fe.n_base_elements() == 1 &&
                    fe.element_multiplicity(0) == fe.n_components(),
                  ExcMessage("the ParaView output samples a vector-valued "
                             "element made of one scalar element (" +
                             fe.get_name() + " is not)"));
      const auto first          = disc.dof_handler().begin_active();
      degree                    = disc.higher_order_cell(first).degree;
      n_nodes                   = (degree + 1) * (degree + 1);
      n_functions               = fe.base_element(0).n_dofs_per_cell();
      const std::size_t n_cells = disc.triangulation().n_active_cells();
      const std::size_t bytes_per_cell =
        sizeof(double) * n_nodes * (3 * n_functions + 3 + n_nodes);
      if (bytes_per_cell * n_cells > max_cached_bytes)
        return;
      const auto fe_values = node_fe_values(disc, degree);
      vtk_cells.resize(n_cells);
      positions.resize(n_cells * n_nodes * 2);
      values.resize(n_cells * n_nodes * n_functions);
      gradients.resize(2 * values.size());
      for (const auto &cell : disc.dof_handler().active_cell_iterators())
        {
          const std::size_t c = cell->active_cell_index();
          fill_cell_shapes(*fe_values,
                           disc,
                           cell,
                           vtk_cells[c],
                           {&positions[c * n_nodes * 2],
                            &values[c * n_nodes * n_functions],
                            &gradients[2 * c * n_nodes * n_functions]});
        }
    }

    bool
    cached() const
    {
      return !vtk_cells.empty();
    }

    // The shapes of a cell (cached()).
    CellShapes
    shapes(const std::size_t c) const
    {
      return {&positions[c * n_nodes * 2],
              &values[c * n_nodes * n_functions],
              &gradients[2 * c * n_nodes * n_functions]};
    }

    unsigned int degree      = 0;
    unsigned int n_nodes     = 0;
    unsigned int n_functions = 0;
    // In the order of the active cells; empty: not cached.
    std::vector<HigherOrderCell> vtk_cells;
    std::vector<double>          positions, values, gradients;

    std::array<std::shared_ptr<HigherOrderPiece>, 2> pieces = {
      {std::make_shared<HigherOrderPiece>(),
       std::make_shared<HigherOrderPiece>()}};
    unsigned int next_piece = 0;
  };

  namespace
  {
    /**
     * One body as higher-order VTK cells (Discretization::
     * higher_order_cell()): every cell has its own nodes (the stresses are
     * discontinuous); fields are sampled at the node points and turned into
     * node coefficients, so displacement, velocity and the geometry are
     * exact; the stresses interpolate the element's stresses at the node
     * points. Fills `piece`, whose arrays keep their memory from one write
     * to the next.
     */
    void
    sample_higher_order_cells(const ElasticBody<2> &body,
                              const Vector<double> &contact_pressure,
                              const double          time,
                              const SolutionWriter::BodySampling &sampling,
                              HigherOrderPiece                   &piece)
    {
      const auto     &disc = body.discretization();
      const DoFFields fields(body, contact_pressure);
      const auto &[displacement, velocity, pressure] = fields.vectors;

      piece.time            = time;
      piece.degree          = sampling.degree;
      piece.vtk_type        = 0;
      const unsigned int n  = sampling.n_nodes;
      const unsigned int mb = sampling.n_functions;
      const auto        &fe = disc.fe();
      const unsigned int m  = fe.n_dofs_per_cell();
      // Not cached: the shapes of each cell through FEValues.
      const auto fe_values =
        sampling.cached() ? nullptr : node_fe_values(disc, piece.degree);
      std::vector<double>    scratch(fe_values ? n * (2 + 3 * mb) : 0);
      HigherOrderCell        uncached_cell;
      const CellShapesToFill uncached{scratch.data(),
                                      scratch.data() + 2 * n,
                                      scratch.data() + 2 * n + n * mb};
      // The unknowns of a cell as (component, scalar function).
      std::vector<std::pair<unsigned int, unsigned int>> component_and_index(m);
      for (unsigned int i = 0; i < m; ++i)
        component_and_index[i] = fe.system_to_component_index(i);

      // Several MPI ranks: this rank's cells (UnknownExchange::owns_cell).
      const UnknownExchange &exchange = body.exchange();
      piece.n_cells                   = 0;
      for (unsigned int c = 0; c < disc.triangulation().n_active_cells(); ++c)
        piece.n_cells += exchange.owns_cell(c);
      const std::size_t n_points = std::size_t(n) * piece.n_cells;
      piece.points.resize(3 * n_points);
      const auto arrays = point_arrays(true);
      piece.point_data.resize(arrays.size());
      for (unsigned int a = 0; a < arrays.size(); ++a)
        piece.point_data[a].resize(arrays[a].second * n_points);
      // Sampled values (n x components) of: u, v, stresses, contact
      // pressure.
      const unsigned int pressure_column = 4 + stress_names.size();
      FullMatrix<double> samples(n, pressure_column + 1);
      FullMatrix<double> coefficients(n, samples.n());
      std::vector<types::global_dof_index> dof_indices(m);
      // Per component and scalar function: u, v; the pressure (component 0).
      std::vector<double> u_local(2 * mb), v_local(2 * mb), p_local(mb);
      std::size_t         point = 0;
      for (const auto &cell : disc.dof_handler().active_cell_iterators())
        {
          const std::size_t c = cell->active_cell_index();
          if (!exchange.owns_cell(c))
            continue;
          if (fe_values)
            fill_cell_shapes(*fe_values, disc, cell, uncached_cell, uncached);
          const CellShapes       shapes = fe_values ?
                                            CellShapes{uncached.position_coefficients,
                                                 uncached.values,
                                                 uncached.gradients} :
                                            sampling.shapes(c);
          const HigherOrderCell &vtk_cell =
            fe_values ? uncached_cell : sampling.vtk_cells[c];
          AssertThrow(vtk_cell.degree == piece.degree,
                      ExcMessage("cells of different degrees"));
          if (piece.vtk_type == 0)
            piece.vtk_type = vtk_cell.vtk_type;
          cell->get_dof_indices(dof_indices);
          for (unsigned int i = 0; i < m; ++i)
            {
              const auto [component, j]   = component_and_index[i];
              u_local[component * mb + j] = displacement(dof_indices[i]);
              v_local[component * mb + j] = velocity(dof_indices[i]);
              if (component == 0)
                p_local[j] = pressure(dof_indices[i]);
            }
          for (unsigned int k = 0; k < n; ++k)
            {
              const double *const values    = shapes.values + k * mb;
              const double *const gradients = shapes.gradients + 2 * k * mb;
              Tensor<1, 2>        u, v;
              Tensor<2, 2>        grad_u;
              double              p = 0.;
              for (unsigned int c = 0; c < 2; ++c)
                for (unsigned int j = 0; j < mb; ++j)
                  {
                    const double value = values[j];
                    u[c] += value * u_local[c * mb + j];
                    v[c] += value * v_local[c * mb + j];
                    grad_u[c][0] += gradients[2 * j] * u_local[c * mb + j];
                    grad_u[c][1] += gradients[2 * j + 1] * u_local[c * mb + j];
                  }
              for (unsigned int j = 0; j < mb; ++j)
                p += values[j] * p_local[j];
              const auto sigma = stresses(body.material(), grad_u);
              for (unsigned int d = 0; d < 2; ++d)
                {
                  samples(k, d)     = u[d];
                  samples(k, 2 + d) = v[d];
                }
              for (unsigned int s = 0; s < sigma.size(); ++s)
                samples(k, 4 + s) = sigma[s];
              samples(k, pressure_column) = p;
            }
          const bool identity = vtk_cell.values_to_nodes.m() == 0;
          // (n x n) times (n x 10): a loop, BLAS's call costs more.
          if (!identity)
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int column = 0; column < samples.n(); ++column)
                {
                  double sum = 0.;
                  for (unsigned int k = 0; k < n; ++k)
                    sum += vtk_cell.values_to_nodes(i, k) * samples(k, column);
                  coefficients(i, column) = sum;
                }
          const FullMatrix<double> &node_values =
            identity ? samples : coefficients;
          for (unsigned int j = 0; j < n; ++j, ++point)
            {
              for (unsigned int d = 0; d < 2; ++d)
                {
                  piece.points[3 * point + d] =
                    shapes.position_coefficients[2 * j + d];
                  for (unsigned int a = 0; a < 2; ++a)
                    piece.point_data[a][3 * point + d] =
                      node_values(j, 2 * a + d);
                }
              piece.points[3 * point + 2] = 0.;
              for (unsigned int a = 0; a < 2; ++a)
                piece.point_data[a][3 * point + 2] = 0.;
              // stresses and pressure, then the weights
              for (unsigned int s = 0; s <= stress_names.size(); ++s)
                piece.point_data[2 + s][point] = node_values(j, 4 + s);
              piece.point_data.back()[point] = vtk_cell.weights[j];
            }
        }
      AssertDimension(point, n_points);
    }

    // The VTU file of a sampled piece (appended raw data, see
    // AppendedArrays).
    void
    write_higher_order_vtu(std::ostream           &out,
                           const HigherOrderPiece &piece,
                           const bool              compress)
    {
      const unsigned int n_cells = piece.n_cells;
      // (A rank may hold no cell of a body: an empty piece.)
      const unsigned int n =
        n_cells > 0 ? piece.points.size() / 3 / n_cells : 0;
      const auto                arrays = point_arrays(true);
      AppendedArrays            data(compress);
      std::ostringstream        xml;
      const std::vector<double> time{piece.time};
      xml << "<FieldData>\n"
          << data.add("TIME", 1, time)
          << "</FieldData>\n<Piece NumberOfPoints=\"" << piece.points.size() / 3
          << "\" NumberOfCells=\"" << n_cells << "\">\n<Points>\n"
          << data.add("", 3, piece.points) << "</Points>\n<Cells>\n";
      std::vector<std::int64_t> connectivity(n_cells * n), offsets(n_cells);
      for (std::size_t i = 0; i < connectivity.size(); ++i)
        connectivity[i] = i;
      for (unsigned int c = 0; c < n_cells; ++c)
        offsets[c] = (c + 1) * n;
      const std::vector<std::uint8_t> types(n_cells, piece.vtk_type);
      xml << data.add("connectivity", 1, connectivity)
          << data.add("offsets", 1, offsets) << data.add("types", 1, types)
          << "</Cells>\n<PointData RationalWeights=\"RationalWeights\">\n";
      for (unsigned int a = 0; a < arrays.size(); ++a)
        xml << data.add(arrays[a].first, arrays[a].second, piece.point_data[a]);
      std::vector<double> degrees;
      for (unsigned int c = 0; c < n_cells; ++c)
        degrees.insert(degrees.end(),
                       {double(piece.degree), double(piece.degree), 0.});
      xml << "</PointData>\n"
          << "<CellData HigherOrderDegrees=\"HigherOrderDegrees\">\n"
          << data.add("HigherOrderDegrees", 3, degrees)
          << "</CellData>\n</Piece>\n</UnstructuredGrid>\n";
      out << "<?xml version=\"1.0\"?>\n"
          << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
          << data.file_attributes() << ">\n<UnstructuredGrid>\n"
          << xml.str();
      data.write(out);
      out << "</VTKFile>\n";
    }

    // The .pvtu record of the pieces of one output time.
    void
    write_pvtu(std::ostream                   &out,
               const std::vector<std::string> &pieces,
               const bool                      higher_order)
    {
      out << "<?xml version=\"1.0\"?>\n"
          << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
             "byte_order=\"LittleEndian\" header_type=\"UInt32\">\n"
          << "<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData"
          << (higher_order ? " RationalWeights=\"RationalWeights\">\n" : ">\n");
      // deal.II writes its fields as Float32.
      const char *type = higher_order ? "Float64" : "Float32";
      for (const auto &[name, n_components] : point_arrays(higher_order))
        out << "<PDataArray type=\"" << type << "\" Name=\"" << name
            << "\" NumberOfComponents=\"" << n_components << "\"/>\n";
      out << "</PPointData>\n";
      if (higher_order)
        out << "<PCellData HigherOrderDegrees=\"HigherOrderDegrees\">\n"
            << "<PDataArray type=\"Float64\" Name=\"HigherOrderDegrees\" "
               "NumberOfComponents=\"3\"/>\n</PCellData>\n";
      out << "<PPoints><PDataArray type=\"" << type
          << "\" NumberOfComponents=\"3\"/></PPoints>\n";
      for (const auto &piece : pieces)
        out << "<Piece Source=\"" << piece << "\"/>\n";
      out << "</PUnstructuredGrid>\n</VTKFile>\n";
    }
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
                                 const unsigned int n_subdivisions,
                                 const bool         higher_order,
                                 const bool         compress)
    : directory(directory)
    , n_subdivisions(n_subdivisions)
    , higher_order(higher_order)
    , compress(compress)
  {}

  std::vector<Vector<double>>
  contact_pressure_nodal_values(const Scene                         &scene,
                                const std::vector<ContactResult<2>> &results)
  {
    std::vector<Vector<double>> pressures;
    for (const auto &body : scene.bodies)
      pressures.emplace_back(body->n_dofs());
    AssertDimension(results.size(), scene.interactions.size());
    for (unsigned int i = 0; i < results.size(); ++i)
      {
        const std::array<unsigned int, 2> owners = {
          {scene.interactions[i].first_body,
           scene.interactions[i].second_body}};
        for (unsigned int b = 0; b < 2; ++b)
          for (const auto &[dof, p] : results[i].nodal_pressures[b])
            pressures[owners[b]][dof] += p; // surfaces of two interactions
      }
    return pressures;
  }

  std::string
  SolutionWriter::write(const std::vector<ElasticBody<2> *> &bodies,
                        const double                         time,
                        const std::vector<Vector<double>>   &contact_pressures)
  {
    AssertDimension(contact_pressures.size(), bodies.size());
    const std::string number = Utilities::int_to_string(counter++, 4);
    // One piece per body, and on several MPI ranks per body and rank
    // (<body>_<number>.<rank>.vtu): each rank writes its own cells' pieces,
    // rank 0 the records that join them.
    const unsigned int n_ranks    = n_world_ranks();
    const auto         piece_name = [&](const ElasticBody<2> &body,
                                const unsigned int    rank) {
      return body.name() + "_" + number +
             (n_ranks > 1 ? "." + std::to_string(rank) : std::string()) +
             ".vtu";
    };
    std::vector<std::string> pieces, all_pieces;
    for (const auto *body : bodies)
      {
        pieces.push_back(piece_name(*body, world_rank()));
        for (unsigned int rank = 0; rank < n_ranks; ++rank)
          all_pieces.push_back(piece_name(*body, rank));
      }
    const bool        writes_records = world_rank() == 0;
    const std::string pvtu           = "solution_" + number + ".pvtu";
    times_and_names.emplace_back(time, pvtu);

    // Every file by rename: a stopped run leaves complete files (and at most
    // one .tmp per file being written).
    const auto write_records = [directory = directory,
                                all_pieces,
                                pvtu,
                                writes_records,
                                times_and_names = times_and_names,
                                higher_order    = higher_order]() {
      if (!writes_records)
        return;
      write_by_rename(directory + "/" + pvtu, [&](std::ostream &record) {
        try
          {
            write_pvtu(record, all_pieces, higher_order);
          }
        catch (const ExceptionBase &)
          {
            record.setstate(std::ios::badbit);
          }
      });
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
    };

    if (!higher_order)
      {
        // deal.II's DataOut refers to the body's vectors: written here.
        finish();
        // A body whose cells this rank does not hold (their unknowns'
        // numbering released): an empty piece with the arrays of one that
        // it holds (every body has the same fields).
        unsigned int held = 0;
        while (held < bodies.size() &&
               !bodies[held]->discretization().holds_cell_unknowns())
          ++held;
        AssertThrow(held < bodies.size(), ExcInternalError());
        for (unsigned int b = 0; b < bodies.size(); ++b)
          write_by_rename(directory + "/" + pieces[b], [&](std::ostream &out) {
            try
              {
                const bool empty =
                  !bodies[b]->discretization().holds_cell_unknowns();
                write_subdivided_vtu(out,
                                     *bodies[empty ? held : b],
                                     contact_pressures[empty ? held : b],
                                     time,
                                     n_subdivisions,
                                     empty);
              }
            catch (const ExceptionBase &)
              {
                out.setstate(std::ios::badbit); // see close_and_check
              }
          });
        write_records();
        return pvtu;
      }

    // The fields are sampled now; compression and writing (most of the
    // cost) run in the background while the time loop goes on. One write
    // is in flight at a time: the previous one is finished first.
    // The bodies are sampled side by side (the time loop waits for them):
    // all but the last in tasks, the last here.
    if (samplings.size() != bodies.size())
      samplings.assign(bodies.size(), nullptr);
    // Each body fills the piece it did not fill last time: the other one
    // may still be being written until finish() below.
    std::vector<std::shared_ptr<const HigherOrderPiece>> samples(bodies.size());
    std::vector<std::future<void>>                       sampling;
    const auto sample = [&](const unsigned int b) {
      if (!bodies[b]->discretization().holds_cell_unknowns())
        {
          // A body whose cells this rank does not hold: an empty piece.
          auto empty  = std::make_shared<HigherOrderPiece>();
          empty->time = time;
          empty->point_data.resize(point_arrays(true).size());
          samples[b] = empty;
          return;
        }
      if (!samplings[b])
        samplings[b] =
          std::make_shared<BodySampling>(bodies[b]->discretization());
      BodySampling &body_sampling = *samplings[b];
      const auto   &piece      = body_sampling.pieces[body_sampling.next_piece];
      body_sampling.next_piece = 1 - body_sampling.next_piece;
      sample_higher_order_cells(*bodies[b],
                                contact_pressures[b],
                                time,
                                body_sampling,
                                *piece);
      samples[b] = piece;
    };
    for (unsigned int b = 0; b + 1 < bodies.size(); ++b)
      sampling.push_back(std::async(std::launch::async, sample, b));
    sample(bodies.size() - 1);
    for (auto &task : sampling)
      task.get();
    finish();
    pending = std::async(
      std::launch::async,
      [directory = directory,
       pieces,
       samples  = std::move(samples),
       compress = compress,
       write_records]() {
        for (unsigned int b = 0; b < pieces.size(); ++b)
          write_by_rename(directory + "/" + pieces[b], [&](std::ostream &out) {
            try
              {
                write_higher_order_vtu(out, *samples[b], compress);
              }
            catch (const ExceptionBase &)
              {
                out.setstate(std::ios::badbit);
              }
          });
        write_records();
      });
    return pvtu;
  }



  void
  SolutionWriter::finish()
  {
    if (pending.valid())
      pending.get(); // rethrows a failed write
  }



  SolutionWriter::~SolutionWriter()
  {
    if (pending.valid())
      pending.wait(); // errors were reported by finish(), if called
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
    bipenalty = parameters.bipenalty;
    if (bipenalty)
      out << "# bipenalty: bipenalty_kinetic_energy_J_per_m is the kinetic "
             "energy of the mass penalty, bipenalty_switching_work_J_per_m "
             "the energy it brought in since t = 0 as it appeared and "
             "vanished; total_energy = kinetic + strain + contact + "
             "contact_damping_work + bipenalty_kinetic_energy - "
             "bipenalty_switching_work\n";
    with_boundary_solve = parameters.mass_redistribution;
    if (with_boundary_solve)
      out << "# mass redistribution: kinetic_energy is that of the interior "
             "unknowns (the contact surfaces are massless); "
             "boundary_solve_work [1] is the number of contact evaluations "
             "(Newton residuals) of the quasi-static boundary solve in the "
             "step of the row\n";
    out << "time,contact_force,max_contact_pressure,max_gauss_point_pressure,"
           "kinetic_energy,"
           "strain_energy,contact_energy,contact_damping_work,";
    if (bipenalty)
      out << "bipenalty_kinetic_energy_J_per_m,"
             "bipenalty_switching_work_J_per_m,";
    out << "total_energy";
    if (scene.reference)
      out << ",analytic_contact_force,analytic_max_contact_pressure";
    if (with_boundary_solve)
      out << ",boundary_solve_work";
    out << '\n';
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
    out << rows;
    out.flush();
    rows.clear();
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
                       const EnergyBalance &energy,
                       const unsigned int   boundary_solve_work)
  {
    // std::to_chars at 10 significant digits writes what an ostream with
    // setprecision(10) writes (printf's %.10g), without its locale and
    // stream machinery.
    const auto add = [this](const double value) {
      char       digits[32];
      const auto end = std::to_chars(digits,
                                     digits + sizeof(digits),
                                     value,
                                     std::chars_format::general,
                                     10)
                         .ptr;
      rows.append(digits, end);
    };
    const double factor = scene.symmetry_factor;
    for (const double value : {time,
                               contact_force,
                               max_pressure,
                               max_gauss_point_pressure,
                               factor * energy.kinetic,
                               factor * energy.strain,
                               factor * energy.contact,
                               factor * energy.contact_damping})
      {
        add(value);
        rows += ',';
      }
    if (bipenalty)
      for (const double value : {factor * energy.bipenalty_kinetic,
                                 factor * energy.bipenalty_switching})
        {
          add(value);
          rows += ',';
        }
    add(factor * energy.total());
    if (scene.reference)
      {
        // One solve of the reference per row: its pressure from its force.
        const double force = scene.reference->contact_force(time);
        rows += ',';
        add(force);
        rows += ',';
        add(scene.reference->peak_pressure_of_force(force));
      }
    if (with_boundary_solve)
      rows += ',' + std::to_string(boundary_solve_work);
    rows += '\n';
    // Whole rows only reach the file: a killed run leaves complete ones.
    if (rows.size() > (1 << 16))
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
      // All the digits: the ParaView pressure is compared with them.
      out << '\n' << std::setprecision(17);
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
