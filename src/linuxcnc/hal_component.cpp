// The only file that talks to hal.h (compiled with -DULAPI, linked with liblinuxcnchal).
#include "trueaxis/linuxcnc/hal_component.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include <hal.h>

namespace trueaxis::linuxcnc {
namespace {

hal_pin_dir_t ToHal(PinDirection d) { return d == PinDirection::kIn ? HAL_IN : HAL_OUT; }

// Pin data slots must live in HAL memory (hal_malloc), one pointer per pin.
template <typename Slot>
Slot** AllocateSlot(const std::string& pin) {
  void* memory = hal_malloc(sizeof(Slot*));
  if (memory == nullptr) throw std::runtime_error(fmt::format("HAL: out of shared memory for pin {}", pin));
  return static_cast<Slot**>(memory);
}

void Check(int rc, const std::string& pin) {
  if (rc != 0) throw std::runtime_error(fmt::format("HAL refused pin {} (error {})", pin, rc));
}

}  // namespace

HalComponent::HalComponent(const std::string& name) : name_(name) {
  id_ = hal_init(name.c_str());
  if (id_ < 0)
    throw std::runtime_error(fmt::format(
        "hal_init(\"{}\") failed (error {}): is LinuxCNC (or halrun) running, and the name not taken?", name, id_));
}

HalComponent::~HalComponent() {
  if (id_ >= 0) hal_exit(id_);
}

Pin<double> HalComponent::FloatPin(const std::string& suffix, PinDirection direction) {
  const std::string pin = name_ + "." + suffix;
  hal_float_t** slot = AllocateSlot<hal_float_t>(pin);
  Check(hal_pin_float_new(pin.c_str(), ToHal(direction), slot, id_), pin);
  **slot = 0.0;
  return Pin<double>(reinterpret_cast<volatile double**>(slot));
}

Pin<bool> HalComponent::BitPin(const std::string& suffix, PinDirection direction) {
  const std::string pin = name_ + "." + suffix;
  hal_bit_t** slot = AllocateSlot<hal_bit_t>(pin);
  Check(hal_pin_bit_new(pin.c_str(), ToHal(direction), slot, id_), pin);
  **slot = false;
  return Pin<bool>(slot);
}

Pin<std::int32_t> HalComponent::S32Pin(const std::string& suffix, PinDirection direction) {
  const std::string pin = name_ + "." + suffix;
  hal_s32_t** slot = AllocateSlot<hal_s32_t>(pin);
  Check(hal_pin_s32_new(pin.c_str(), ToHal(direction), slot, id_), pin);
  **slot = 0;
  return Pin<std::int32_t>(reinterpret_cast<volatile std::int32_t**>(slot));
}

void HalComponent::Ready() {
  const int rc = hal_ready(id_);
  if (rc != 0) throw std::runtime_error(fmt::format("hal_ready({}) failed (error {})", name_, rc));
}

}  // namespace trueaxis::linuxcnc
