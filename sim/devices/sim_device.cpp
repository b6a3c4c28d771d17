// The parts of the device interface every kind shares: sample collection and seeds.
#include "devices/sim_device.hpp"

#include <algorithm>

namespace sear {
namespace {

// Independent noise streams per device from one run seed (splitmix64's finaliser).
std::uint64_t mix(std::uint64_t seed, std::uint64_t salt) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (salt + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

void SampleSink::add(std::int64_t time_ns, std::uint64_t index, std::uint32_t input,
                     std::initializer_list<double> values) {
  if (samples_.size() == SEAR_LINK_MAX_SAMPLES) return;
  sear_link_sample s{};
  s.time_ns = time_ns;
  s.index = index;
  s.input = input;
  std::copy_n(values.begin(), std::min<std::size_t>(values.size(), SEAR_LINK_SAMPLE_VALUES), s.value);
  samples_.push_back(s);
}

const std::vector<sear_link_sample>& SampleSink::sorted() {
  std::stable_sort(samples_.begin(), samples_.end(),
                   [](const sear_link_sample& a, const sear_link_sample& b) { return a.time_ns < b.time_ns; });
  return samples_;
}

std::uint32_t DeviceHost::add_input(sear_link_input input) {
  const auto index = static_cast<std::uint32_t>(inputs_.size());
  input.seed = mix(run_seed_, index);
  inputs_.push_back(input);
  return index;
}

// Salts above 2^32 keep these streams apart from the inputs' (salted by their index).
std::uint64_t DeviceHost::seed(std::uint64_t salt) const {
  return mix(run_seed_, (1ull << 32) + device_ * 256 + salt);
}

sear_link_input blank_input(sear_input_kind kind) {
  sear_link_input in{};
  in.kind = kind;
  std::fill(std::begin(in.pins), std::end(in.pins), SEAR_LINK_NO_PIN);
  return in;
}

}  // namespace sear
