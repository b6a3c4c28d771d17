// The merge of EdgeStreams (see edge_streams.hpp).
#include "exporters/edge_streams.hpp"

#include <algorithm>

namespace sear {
namespace {

// Whether a comes before b: by time, and for equal times by arrival.
bool before(std::int64_t a_ns, std::uint64_t a_seq, std::int64_t b_ns, std::uint64_t b_seq) {
  return a_ns < b_ns || (a_ns == b_ns && a_seq < b_seq);
}

}  // namespace

void EdgeStreams::push(std::size_t stream, const sear_event& e) {
  Stream& q = streams_[stream];
  const Queued item{e, seq_++};
  waiting_ |= std::uint64_t{1} << stream;
  if (q.head == q.items.size() || q.items.back().e.time_ns <= e.time_ns) {
    q.items.push_back(item);
    return;
  }
  // After every change of its time or earlier: it arrived last.
  const auto at = std::upper_bound(q.items.begin() + static_cast<std::ptrdiff_t>(q.head), q.items.end(), e.time_ns,
                                   [](std::int64_t t, const Queued& x) { return t < x.e.time_ns; });
  q.items.insert(at, item);
}

// The stream that comes first hands on its changes in a row up to where another's first would
// come between: a UART line's edges, thousands behind a 500 kbaud port, mostly follow each other,
// so the streams are compared once a run rather than once a change.
void EdgeStreams::take_until(std::int64_t until_ns, std::vector<sear_event>& out) {
  for (;;) {
    Stream* first = nullptr;
    std::int64_t next_ns = INT64_MAX;  // the first change of the other streams
    std::uint64_t next_seq = UINT64_MAX;
    for (std::uint64_t left = waiting_; left; left &= left - 1) {
      Stream& q = streams_[static_cast<std::size_t>(__builtin_ctzll(left))];
      const Queued& front = q.items[q.head];
      if (!first || before(front.e.time_ns, front.seq, first->items[first->head].e.time_ns,
                           first->items[first->head].seq)) {
        if (first) {
          next_ns = first->items[first->head].e.time_ns;
          next_seq = first->items[first->head].seq;
        }
        first = &q;
      } else if (before(front.e.time_ns, front.seq, next_ns, next_seq)) {
        next_ns = front.e.time_ns;
        next_seq = front.seq;
      }
    }
    if (!first || first->items[first->head].e.time_ns > until_ns) return;
    std::size_t i = first->head;
    const std::size_t n = first->items.size();
    do {
      out.push_back(first->items[i++].e);
    } while (i < n && first->items[i].e.time_ns <= until_ns &&
             before(first->items[i].e.time_ns, first->items[i].seq, next_ns, next_seq));
    first->head = i;
    // What was handed on is dropped once it is three quarters of the stream, so that a change
    // waiting behind a 500 kbaud line is moved a third of a time on average.
    if (first->head == n) {
      first->items.clear();
      first->head = 0;
      waiting_ &= ~(std::uint64_t{1} << (first - streams_.data()));
    } else if (first->head > n / 4 * 3) {
      first->items.erase(first->items.begin(), first->items.begin() + static_cast<std::ptrdiff_t>(first->head));
      first->head = 0;
    }
  }
}

}  // namespace sear
