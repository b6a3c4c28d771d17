// The merge of EdgeStreams (see edge_streams.hpp).
#include "exporters/edge_streams.hpp"

#include <algorithm>

namespace sear {

void EdgeStreams::push(std::size_t stream, const sear_event& e) {
  std::deque<Queued>& q = streams_[stream];
  const Queued item{e, seq_++};
  if (q.empty() || q.back().e.time_ns <= e.time_ns) {
    q.push_back(item);
    return;
  }
  // After every change of its time or earlier: it arrived last.
  const auto at = std::upper_bound(q.begin(), q.end(), e.time_ns,
                                   [](std::int64_t t, const Queued& x) { return t < x.e.time_ns; });
  q.insert(at, item);
}

void EdgeStreams::take_until(std::int64_t until_ns, std::vector<sear_event>& out) {
  for (;;) {
    std::deque<Queued>* first = nullptr;
    for (auto& q : streams_) {
      if (q.empty() || q.front().e.time_ns > until_ns) continue;
      if (!first || q.front().e.time_ns < first->front().e.time_ns ||
          (q.front().e.time_ns == first->front().e.time_ns && q.front().seq < first->front().seq))
        first = &q;
    }
    if (!first) return;
    out.push_back(first->front().e);
    first->pop_front();
  }
}

}  // namespace sear
