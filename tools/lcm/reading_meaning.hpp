// What the values of a device's samples mean (link/lockstep_link.h, enum sear_input_kind), by the
// device's element in the project, for the quantity and unit fields of SEAR's READING messages.
#pragma once

#include <string>
#include <vector>

namespace sear {

struct ReadingMeaning {
  std::vector<const char*> quantity;  // per value of a sample
  std::vector<const char*> unit;
};

// A kind the table does not know yet gets all six values, named value0..value5, unit "?".
const ReadingMeaning& reading_meaning(const std::string& element);

}  // namespace sear
