#pragma once
// Shared set-up of the vision tests: the example marker, a 640×480 camera with
// barrel distortion, and the reference K read from clean renders at 20 °C.
#include "trueaxis/vision/marker_measurement.hpp"
#include "trueaxis/vision/virtual_camera.hpp"
#include "trueaxis/vision/vision_day.hpp"

namespace trueaxis::vision::testing {

inline MarkerDescription TestMarker() { return MarkerDescription{}; }

inline CameraModel TestCamera() { return CameraModel::ForField(640, 480, 110, TestMarker().distance_mm, -0.05); }

inline const VirtualCamera& TestVirtualCamera() {
  static const VirtualCamera cam(TestCamera());
  return cam;
}

// The marker with its reference K set from clean renders at the standard temperature.
inline MarkerDescription ReferencedMarker() {
  static const MarkerDescription m = [] {
    MarkerDescription marker = TestMarker();
    std::vector<MarkerReading> ref;
    for (double a : {42.0, 45.0, 48.0}) {
      MarkerScene s;
      s.angle_deg = a;
      ref.push_back(MeasureMarker(TestVirtualCamera().RenderMarker(marker, s, {}, 7), TestCamera(), marker, "ref"));
    }
    std::tie(marker.reference_k1, marker.reference_k2) = ReferenceK(ref);
    return marker;
  }();
  return m;
}

}  // namespace trueaxis::vision::testing
