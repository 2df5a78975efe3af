// Layer 4: linear elastic material, plane strain or plane stress.
#ifndef isoimpact_material_h
#define isoimpact_material_h

#include <deal.II/base/symmetric_tensor.h>

#include <cmath>

namespace isoimpact
{

  struct ElasticMaterial
  {
    double youngs_modulus = 1000.; // Pa
    double poisson_ratio  = 0.2;
    double density        = 1.; // kg/m^3
    bool   plane_strain   = true;

    double
    lame_mu() const
    {
      return youngs_modulus / (2. * (1. + poisson_ratio));
    }

    // In plane stress the in-plane behaviour is that of a modified lambda.
    double
    lame_lambda() const
    {
      const double lambda = youngs_modulus * poisson_ratio /
                            ((1. + poisson_ratio) * (1. - 2. * poisson_ratio));
      const double mu = lame_mu();
      return plane_strain ? lambda : 2. * lambda * mu / (lambda + 2. * mu);
    }

    // Speed of the fastest (dilatational) wave in the plane, m/s.
    double
    dilatational_wave_speed() const
    {
      return std::sqrt((lame_lambda() + 2. * lame_mu()) / density);
    }

    template <int dim>
    dealii::SymmetricTensor<2, dim>
    stress(const dealii::SymmetricTensor<2, dim> &strain) const
    {
      return lame_lambda() * trace(strain) *
               dealii::unit_symmetric_tensor<dim>() +
             2. * lame_mu() * strain;
    }

    // Out-of-plane stress sigma_zz (plane strain; zero in plane stress).
    template <int dim>
    double
    out_of_plane_stress(const dealii::SymmetricTensor<2, dim> &strain) const
    {
      return plane_strain ? lame_lambda() * trace(strain) : 0.;
    }
  };
} // namespace isoimpact

#endif
