#pragma once
// HalComponent: one LinuxCNC userspace HAL component (hal.h from linuxcnc-uspace-dev):
// hal_init on construction, pins created in HAL shared memory, hal_ready once every pin
// exists, hal_exit on destruction (docs/linuxcnc.md). A pin is read and written through
// the pointer slot HAL keeps for it (the slot is re-pointed when the pin is linked to a
// signal), so a Pin<T> reads/writes whatever the signal carries.
#include <cstdint>
#include <string>

namespace trueaxis::linuxcnc {

enum class PinDirection { kIn, kOut };

// A pin's data slot in HAL memory: **slot is the value. T is double, bool or std::int32_t.
template <typename T>
class Pin {
 public:
  Pin() = default;
  // Right after the pin is created: *slot points at the pin's own storage (HAL's "dummysig").
  explicit Pin(volatile T** slot) : slot_(slot), unlinked_(*slot) {}
  bool valid() const { return slot_ != nullptr; }
  T Get() const { return **slot_; }
  void Set(T value) const { **slot_ = value; }
  // The pin is netted to a signal: HAL re-points the slot at the signal's value (and back at the
  // pin's own storage on unlink). An input never netted reads what setp put there, 0 by default.
  bool Linked() const { return *slot_ != unlinked_; }

 private:
  volatile T** slot_ = nullptr;
  volatile T* unlinked_ = nullptr;
};

class HalComponent {
 public:
  // hal_init(name). Throws std::runtime_error naming the component when HAL refuses (no
  // LinuxCNC/halrun session running, or the name is taken).
  explicit HalComponent(const std::string& name);
  ~HalComponent();  // hal_exit: HAL removes the component and its pins
  HalComponent(const HalComponent&) = delete;
  HalComponent& operator=(const HalComponent&) = delete;

  const std::string& name() const { return name_; }
  // "<component>.<suffix>"; throws std::runtime_error naming the pin when HAL refuses it.
  Pin<double> FloatPin(const std::string& suffix, PinDirection direction);
  Pin<bool> BitPin(const std::string& suffix, PinDirection direction);
  Pin<std::int32_t> S32Pin(const std::string& suffix, PinDirection direction);
  // Every pin exists: halcmd's `loadusr -W` returns, nets may be made.
  void Ready();

 private:
  std::string name_;
  int id_ = -1;
};

}  // namespace trueaxis::linuxcnc
