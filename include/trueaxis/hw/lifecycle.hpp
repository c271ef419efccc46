#pragma once
// The lifecycle of a hardware component, as ros2_control's hardware interfaces
// have it (on_configure, on_activate, on_deactivate):
//
//   unconfigured ──Configure──► inactive ──Activate──► active ──Deactivate──► inactive
//
//  * Configure: check the settings, size the buffers — may allocate, may fail
//    (with a reason), never talks to the machine.
//  * Activate: start exchanging with the machine (connect, handshake) — may
//    block for a timeout and may fail; a link that cannot connect yet may still
//    be used: its Read/Write fail, and it retries on its own.
//  * Deactivate: stop exchanging (close the connection); Activate may follow.
//
// Read/Write (CncLink, TemperatureSource) are the real-time part and belong to
// the active state. Implementations that need no step keep the defaults.
#include <string>

namespace trueaxis::hw {

enum class LifecycleState { kUnconfigured, kInactive, kActive };

class HardwareLifecycle {
 public:
  virtual ~HardwareLifecycle() = default;
  virtual bool Configure(std::string* error) { return true; }
  virtual bool Activate(std::string* error) { return true; }
  virtual void Deactivate() {}
};

// Configure then Activate; false with *error naming the step that failed.
inline bool ConfigureAndActivate(HardwareLifecycle& component, std::string* error) {
  std::string why;
  if (!component.Configure(&why)) {
    if (error) *error = "configure: " + why;
    return false;
  }
  if (!component.Activate(&why)) {
    if (error) *error = "activate: " + why;
    return false;
  }
  return true;
}

}  // namespace trueaxis::hw
