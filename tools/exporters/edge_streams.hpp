// Pin changes from a few streams, each in time order, handed on in one order: by time, and for
// equal times by arrival. The capture's waveform takes a MCU's events and each UART line's bit
// edges this way.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "lockstep_link.h"

namespace sear {

// What a heap over all the changes gives, for a look at each stream's first: a 500 kbaud line
// keeps some 10^4 edges waiting, and the heap's pops were a tenth of the reference rover's
// simulator time. A change that comes earlier than its stream's last is put in its place.
class EdgeStreams {
 public:
  // At most 64 streams (a bit each in waiting_).
  explicit EdgeStreams(std::size_t streams)
      : streams_(streams <= 64 ? streams : throw std::invalid_argument("EdgeStreams: more than 64 streams")) {}

  void push(std::size_t stream, const sear_event& e);
  // Appends every change at or before until_ns to `out`, in order, and forgets it.
  void take_until(std::int64_t until_ns, std::vector<sear_event>& out);

 private:
  struct Queued {
    sear_event e;
    std::uint64_t seq;  // arrival
  };
  struct Stream {
    std::vector<Queued> items;
    std::size_t head = 0;  // items before it were handed on
  };
  std::vector<Stream> streams_;
  std::uint64_t waiting_ = 0;  // bit n: stream n has changes not handed on (a run's 17 are mostly empty)
  std::uint64_t seq_ = 0;
};

}  // namespace sear
