// Surface materials. A material with a diffuse part receives caustics (it is in the receiver mask);
// a material with a specular part (mirror reflection, glass reflection or refraction) creates them.
#pragma once

#include <string>

#include "core/config.h"
#include "core/math.h"

namespace causticbench {

enum class MaterialKind { diffuse, glossy, mirror, glass, diffuse_mirror };

struct Material {
  MaterialKind kind = MaterialKind::diffuse;
  Color albedo{0.8f};        // diffuse part: diffuse, glossy, diffuse_mirror
  Color specular{0.0f};      // glossy: Phong lobe weight
  float exponent = 20.0f;    // glossy: Phong exponent
  Color reflectance{1.0f};   // mirror, diffuse_mirror: reflectance at normal incidence (or scale of conductor Fresnel)
  bool conductor = false;    // mirror: use conductor Fresnel with eta + i k instead of a constant reflectance
  Color eta{0.2f};
  Color k{3.0f};
  float ior = 1.5f;          // glass: index of refraction (outside medium is 1)
  Color absorption{0.0f};    // glass: Beer-Lambert absorption coefficient per scene unit, per channel

  bool receives_caustics() const {
    return kind == MaterialKind::diffuse || kind == MaterialKind::glossy || kind == MaterialKind::diffuse_mirror;
  }
  bool is_specular() const {
    return kind == MaterialKind::mirror || kind == MaterialKind::glass || kind == MaterialKind::diffuse_mirror;
  }
  // Mirror reflectance for an incident cosine (constant, or conductor Fresnel times reflectance).
  Color mirror_reflectance(float cos_incident) const;
};

Material read_material(const ConfigNode& node);
std::string material_kind_name(MaterialKind kind);

}  // namespace causticbench
