#pragma once
// Non-contact temperature of the virtual tool (docs/tool-thermal.md,
// "Virtual thermal camera and pyrometers").
//
// The camera looks at the tool from the side: image row r shows the axial
// position z = (r + 0.5)·mm_per_px − margin_mm from the tip (tip near the
// top), column c the lateral position x = (c + 0.5)·mm_per_px − width/2.
// A pixel on the tool or holder reads the surface temperature T through a
// radiometric error: T_read = T_refl + (ε_true/ε_set)·(T − T_refl) (the
// linearised grey-body error of a wrong emissivity setting; T_refl = the
// ambient, reflected by the surface), plus Gaussian noise (NETD), occasional
// reflections (a hot spot of +reflection_c over a few pixels) and, with
// coolant on, a film over part of the wetted pixels that reads the coolant's
// temperature. Background pixels read the ambient. Pyrometer spots read the
// same model at a zone's centre.
#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "trueaxis/tooltherm/virtual_tool.hpp"
#include "trueaxis/tooltherm/zone_temperature.hpp"

namespace trueaxis::tooltherm {

struct ThermalCameraOptions {
  double mm_per_px = 1.0;
  double margin_mm = 4.0;
  double emissivity_true = 0.85;   // of the surface
  double emissivity_set = 0.95;    // what the camera assumes
  double noise_c = 0.3;            // per pixel (NETD), 1σ
  double reflection_probability = 0.05;  // per frame
  double reflection_c = 15.0;
  double coolant_film_fraction = 0.4;    // of the wetted pixels, while coolant flows
  double pyrometer_noise_c = 0.2;
  int pyrometer_spots_per_zone = 1;
};

struct CameraScene {
  bool coolant = false;
  double coolant_c = 20;
  double ambient_c = 20;
};

// Image size for a tool (rows, cols) and its zones on that image: each zone's rows span
// its band, its columns the middle 60 % of the part's diameter (at least one pixel).
cv::Size ThermalImageSize(const ToolDescription& tool, const ThermalCameraOptions& o);
std::vector<PixelZone> ImageZonesFor(const ToolDescription& tool, const ThermalCameraOptions& o);

// One frame in °C (CV_32F).
cv::Mat RenderThermalImage(const VirtualTool& tool, const CameraScene& scene, const ThermalCameraOptions& o,
                           std::mt19937_64& rng);
// pyrometer_spots_per_zone readings per zone of the tool, spread evenly along the zone's band.
std::vector<SpotReading> ReadPyrometers(const VirtualTool& tool, const CameraScene& scene,
                                        const ThermalCameraOptions& o, std::mt19937_64& rng);

}  // namespace trueaxis::tooltherm
