#include "core/material.h"

#include "core/optics.h"

namespace causticbench {

Color Material::mirror_reflectance(float cos_incident) const {
  if (!conductor) return reflectance;
  return reflectance * fresnel_conductor(cos_incident, eta, k);
}

std::string material_kind_name(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::diffuse: return "diffuse";
    case MaterialKind::glossy: return "glossy";
    case MaterialKind::mirror: return "mirror";
    case MaterialKind::glass: return "glass";
    case MaterialKind::diffuse_mirror: return "diffuse_mirror";
  }
  return "unknown";
}

Material read_material(const ConfigNode& node) {
  Material material;
  std::string type = node.choice("type", {"diffuse", "glossy", "mirror", "glass", "diffuse_mirror"});
  auto color = [&](const std::string& key, Color fallback, double max_value) {
    return Color(node.rgb_or(key, glm::dvec3(fallback), 0.0, max_value));
  };
  if (type == "diffuse") {
    material.kind = MaterialKind::diffuse;
    material.albedo = color("albedo", Color(0.8f), 1.0);
  } else if (type == "glossy") {
    material.kind = MaterialKind::glossy;
    material.albedo = color("albedo", Color(0.5f), 1.0);
    material.specular = color("specular", Color(0.3f), 1.0);
    material.exponent = static_cast<float>(node.number_or("exponent", 20.0, 1.0, 1e5));
    if (max_component(material.albedo + material.specular) > 1.0f) {
      node.fail("specular", "albedo + specular <= 1 in every channel (energy conservation)", "a larger sum");
    }
  } else if (type == "mirror") {
    material.kind = MaterialKind::mirror;
    material.reflectance = color("reflectance", Color(1.0f), 1.0);
    if (std::optional<ConfigNode> conductor = node.optional_child("conductor")) {
      material.conductor = true;
      material.eta = Color(conductor->rgb("eta", 1e-3, 100.0));
      material.k = Color(conductor->rgb("k", 0.0, 100.0));
      conductor->finish();
    }
  } else if (type == "glass") {
    material.kind = MaterialKind::glass;
    material.ior = static_cast<float>(node.number_or("ior", 1.5, 1.0, 4.0));
    material.absorption = color("absorption", Color(0.0f), 1e6);
  } else {
    material.kind = MaterialKind::diffuse_mirror;
    material.albedo = color("albedo", Color(0.5f), 1.0);
    material.reflectance = color("reflectance", Color(0.5f), 1.0);
    if (max_component(material.albedo + material.reflectance) > 1.0f) {
      node.fail("reflectance", "albedo + reflectance <= 1 in every channel (energy conservation)", "a larger sum");
    }
  }
  node.finish();
  return material;
}

}  // namespace causticbench
