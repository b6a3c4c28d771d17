// What the values of a device's samples (the truth its model in the firmware's process is given)
// and of its readings (what that model gave the firmware) mean (link/lockstep_link.h, enum
// sear_input_kind and struct sear_link_reading), by the device's element in the project, for the
// quantity and unit fields of SEAR's READING messages, the sensors CSV and its plots. Where a
// reading measures the same quantity as the truth it has the same name and unit.
#pragma once

#include <string>
#include <vector>

namespace sear {

struct ReadingMeaning {
  std::vector<const char*> quantity;  // per value
  std::vector<const char*> unit;
};

// Of a sample. A kind the table does not know yet gets all six values, named value0..value5, unit "?".
const ReadingMeaning& reading_meaning(const std::string& element);
// Of a reading (RunTap::on_reading's values), the same way.
const ReadingMeaning& output_meaning(const std::string& element);

}  // namespace sear
