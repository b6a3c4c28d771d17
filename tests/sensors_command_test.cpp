// `sear sensors` held to the table of device kinds and to the loader that reads the same table: the
// JSON lists exactly the table's kinds with every wire and parameter, its defaults are the values the
// loader gives an element that leaves them out, its ranges are the ones the loader refuses values
// by, the text names every element and attribute, and docs/project.md's reference between its
// markers is exactly `sear sensors --markdown` (scripts/update-device-reference.sh rewrites it).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "scene/device_kind.hpp"
#include "scene/diagnostics.hpp"
#include "scene/project_loader.hpp"
#include "command_output.hpp"
#include "temp_dir.hpp"

namespace sear {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Type = DeviceParam::Type;

// `sear ARGS`' standard output; the test fails unless it exits 0.
std::string sear_output(const std::string& args) {
  const std::string command = std::string(SEAR_BINARY) + " " + args;
  const test::CommandOutput run = test::command_output(command);
  EXPECT_EQ(run.exit_code, 0) << command << " failed";
  return run.out;
}

const json& member(const json& list, const char* attribute) {
  for (const json& row : list)
    if (row.at("attribute") == attribute) return row;
  static const json none;
  ADD_FAILURE() << "no '" << attribute << "' in " << list.dump();
  return none;
}

// The placement attributes the loader reads for each Mount (read_device in sim/scene/mcu_loader.cpp).
std::vector<std::string> mount_attributes(Mount mount) {
  switch (mount) {
    case Mount::None: return {};
    case Mount::PositionYaw: return {"pos", "yaw_deg"};
    case Mount::PositionYawPitch: return {"pos", "yaw_deg", "pitch_deg"};
    case Mount::Full: return {"pos", "yaw_deg", "pitch_deg", "roll_deg"};
  }
  return {};
}

// A robot with wheels "left" and "right" (for kinds that name a wheel) and one MCU holding one
// device, `<element name="dev" attributes/>`. Its firmware executable is a shell script: loading checks
// only that it is executable.
class OneDevice {
 public:
  OneDevice() {
    dir_.write("fw", "#!/bin/sh\n");
    fs::permissions(dir_.path() / "fw", fs::perms::owner_all);
  }

  std::optional<ProjectDesc> load(const std::string& element, const std::map<std::string, std::string>& attributes,
                                  Diagnostics& diagnostics) const {
    std::string device = "<" + element + " name=\"dev\"";
    for (const auto& [attribute, value] : attributes) device += " " + attribute + "=\"" + value + "\"";
    const std::string xml = R"(<?xml version="1.0"?>
<project name="sensors">
  <world/>
  <robot name="bot" drive="differential">
    <chassis shape="box" size="0.30 0.18 0.06" mass="1.5"/>
    <wheel name="left" pos="0.04 0.11 -0.01" radius="0.045" width="0.025" mass="0.06"/>
    <wheel name="right" pos="0.04 -0.11 -0.01" radius="0.045" width="0.025" mass="0.06"/>
    <caster pos="-0.11 0 -0.035" radius="0.02"/>
    <mcu name="main" console_uart="-1">
      <firmware executable="fw"/>
      )" + device + R"(/>
    </mcu>
  </robot>
</project>
)";
    return load_project_text(xml, (dir_.path() / "project.xml").string(), diagnostics);
  }

 private:
  test::TempDir dir_;
};

// Values for the wires a kind requires, each on its own resource. `also` wires the first optional
// wire too, for kinds whose check wants at least one output (the MaxBotix).
std::map<std::string, std::string> required_attributes(const DeviceKind& k, bool also = false) {
  std::map<std::string, std::string> out;
  int pin = 2, adc = 0, uart = 1;
  bool optional_given = false;
  for (const DeviceWire& w : k.wires) {
    if (!w.required && (!also || optional_given)) continue;
    optional_given = optional_given || !w.required;
    switch (w.kind) {
      case WireKind::AdcChannel: out[w.attribute] = std::to_string(adc++); break;
      case WireKind::DevicePin:
      case WireKind::McuPin: out[w.attribute] = std::to_string(pin++); break;
      case WireKind::UartPort: out[w.attribute] = std::to_string(uart++); break;
      case WireKind::I2cAddress: out[w.attribute] = "104"; break;
    }
  }
  for (const DeviceParam& p : k.params) {
    if (p.type == Type::Wheel) out[p.attribute] = "left";
    if (p.type == Type::Name && !p.fallback_text) out[p.attribute] = "x";
  }
  return out;
}

// The kind loaded with only what it requires (and, if that alone is refused, one optional wire).
struct Minimal {
  std::map<std::string, std::string> attributes;
  std::optional<ProjectDesc> project;
  std::string errors;
  const DeviceDesc& device() const { return project->robots.at(0).mcus.at(0).devices.at(0); }
};

Minimal load_minimal(const OneDevice& host, const DeviceKind& k) {
  Minimal m;
  for (const bool also : {false, true}) {
    Diagnostics diagnostics;
    m.attributes = required_attributes(k, also);
    m.project = host.load(k.element, m.attributes, diagnostics);
    m.errors = diagnostics.joined();
    if (m.project) break;
  }
  return m;
}

json sensors_json() {
  const std::string out = sear_output("sensors --json");
  try {
    return json::parse(out);
  } catch (const json::exception& e) {
    ADD_FAILURE() << "`sear sensors --json` is not JSON: " << e.what() << "\n" << out;
    return json::array();
  }
}

TEST(SensorsCommand, JsonListsEveryKindOfTheTableWithEveryWireAndParameter) {
  const json kinds = sensors_json();
  const auto& table = device_kinds();
  ASSERT_EQ(kinds.size(), table.size());
  static const std::map<WireKind, std::string> wire_kinds = {
      {WireKind::AdcChannel, "adc_channel"}, {WireKind::DevicePin, "device_pin"}, {WireKind::McuPin, "mcu_pin"},
      {WireKind::UartPort, "uart_port"},     {WireKind::I2cAddress, "i2c_address"}};
  static const std::map<Type, std::string> types = {{Type::Number, "number"}, {Type::Whole, "whole"},
                                                    {Type::Choice, "choice"}, {Type::Name, "text"},
                                                    {Type::Wheel, "wheel"}};
  for (std::size_t i = 0; i < table.size(); ++i) {
    const DeviceKind& k = *table[i];
    const json& j = kinds[i];
    SCOPED_TRACE(k.element);
    EXPECT_EQ(j.at("element"), k.element);
    EXPECT_EQ(j.at("summary"), k.summary);

    std::vector<std::string> mount;
    for (const json& m : j.at("mount")) mount.push_back(m.at("attribute"));
    EXPECT_EQ(mount, mount_attributes(k.mount));

    ASSERT_EQ(j.at("wires").size(), k.wires.size());
    for (std::size_t w = 0; w < k.wires.size(); ++w) {
      const json& jw = j.at("wires")[w];
      EXPECT_EQ(jw.at("attribute"), k.wires[w].attribute);
      EXPECT_EQ(jw.at("kind"), wire_kinds.at(k.wires[w].kind));
      EXPECT_EQ(jw.at("required"), k.wires[w].required);
      EXPECT_EQ(jw.at("meaning"), k.wires[w].meaning);
    }

    ASSERT_EQ(j.at("params").size(), k.params.size());
    for (std::size_t p = 0; p < k.params.size(); ++p) {
      const DeviceParam& row = k.params[p];
      const json& jp = j.at("params")[p];
      EXPECT_EQ(jp.at("attribute"), row.attribute);
      EXPECT_EQ(jp.at("type"), types.at(row.type));
      EXPECT_EQ(jp.at("unit"), row.unit);
      EXPECT_EQ(jp.at("meaning"), row.meaning);
      EXPECT_EQ(jp.at("choices").get<std::vector<std::string>>(), row.choices);
      const bool numeric = row.type == Type::Number || row.type == Type::Whole;
      EXPECT_EQ(jp.at("range").is_null(), !numeric);
    }
  }
}

// Each default in the JSON, in the file's unit, against what the loader made of an element that
// leaves the attribute out (held in SI). nlohmann writes a double in its shortest form that reads
// back to the same double, and the loader multiplies the same fallback by the same to_si, so they
// are compared exactly.
TEST(SensorsCommand, JsonDefaultsAreWhatTheLoaderGivesAnElementThatLeavesThemOut) {
  const json kinds = sensors_json();
  ASSERT_EQ(kinds.size(), device_kinds().size());
  const OneDevice host;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    const DeviceKind& k = *device_kinds()[i];
    SCOPED_TRACE(k.element);
    const Minimal m = load_minimal(host, k);
    ASSERT_TRUE(m.project) << m.errors;
    const DeviceDesc& d = m.device();
    const json& j = kinds[i];

    for (const json& jm : j.at("mount")) {
      const std::string attribute = jm.at("attribute");
      if (attribute == "pos") {
        EXPECT_EQ(jm.at("default").get<std::vector<double>>(),
                  (std::vector<double>{d.position_m.x(), d.position_m.y(), d.position_m.z()}));
      } else {
        // Zero degrees is zero radians whatever the factor.
        const double loaded = attribute == "yaw_deg" ? d.yaw_rad : attribute == "pitch_deg" ? d.pitch_rad : d.roll_rad;
        EXPECT_EQ(jm.at("default").get<double>(), loaded) << attribute;
      }
    }
    for (std::size_t w = 0; w < k.wires.size(); ++w) {
      const json& jw = member(j.at("wires"), k.wires[w].attribute);
      if (m.attributes.count(k.wires[w].attribute)) continue;  // given, not defaulted
      EXPECT_EQ(jw.at("fallback").is_null() ? -1 : jw.at("fallback").get<int>(), d.wires.at(w)) << k.wires[w].attribute;
    }
    for (std::size_t p = 0; p < k.params.size(); ++p) {
      const DeviceParam& row = k.params[p];
      const json& jp = member(j.at("params"), row.attribute);
      SCOPED_TRACE(row.attribute);
      switch (row.type) {
        case Type::Number:
        case Type::Whole:
          EXPECT_FALSE(jp.at("required").get<bool>());
          EXPECT_EQ(jp.at("default").get<double>() * row.to_si, d.values.at(p));
          break;
        case Type::Choice: {
          const auto choices = jp.at("choices").get<std::vector<std::string>>();
          const auto at = std::find(choices.begin(), choices.end(), jp.at("default").get<std::string>());
          ASSERT_NE(at, choices.end());
          EXPECT_EQ(static_cast<double>(at - choices.begin()), d.values.at(p));
          break;
        }
        case Type::Name:
        case Type::Wheel:
          EXPECT_EQ(jp.at("required").get<bool>(), jp.at("default").is_null());
          if (!jp.at("default").is_null()) EXPECT_EQ(jp.at("default").get<std::string>(), d.texts.at(p));
          else EXPECT_EQ(m.attributes.at(row.attribute), d.texts.at(p));
          break;
      }
    }
  }
}

// Just beyond each end of every range the JSON gives, the loader refuses the value, naming the
// attribute and quoting the range's text, with the unit the JSON gives; at each end it takes it.
// "Just beyond" is one part in 1e9 of the bound (at least 1e-9): far below any value a person
// writes, far above a double's resolution (2e-16 relative), so a bound off by any written digit fails.
TEST(SensorsCommand, JsonRangesAreTheOnesTheLoaderRefusesValuesBy) {
  const json kinds = sensors_json();
  ASSERT_EQ(kinds.size(), device_kinds().size());
  const OneDevice host;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    const DeviceKind& k = *device_kinds()[i];
    SCOPED_TRACE(k.element);
    const auto base = load_minimal(host, k).attributes;
    std::vector<json> numbers;
    for (const json& jm : kinds[i].at("mount")) numbers.push_back(jm);
    for (const json& jp : kinds[i].at("params"))
      if (!jp.at("range").is_null()) numbers.push_back(jp);
    for (const json& n : numbers) {
      const std::string attribute = n.at("attribute");
      const json& range = n.at("range");
      const double lo = range.at("min"), hi = range.at("max");
      const bool vector = n.at("type") == "xyz", whole = n.at("type") == "whole";
      const std::string unit = vector ? "" : n.at("unit").get<std::string>();
      const auto load_with = [&](double v, Diagnostics& diagnostics) {
        auto attributes = base;
        char text[64];
        std::snprintf(text, sizeof text, "%.17g", v);
        attributes[attribute] = vector ? std::string(text) + " 0 0" : text;
        return host.load(k.element, attributes, diagnostics);
      };
      const auto refused = [&](double v) {
        Diagnostics diagnostics;
        load_with(v, diagnostics);
        char text[64];
        std::snprintf(text, sizeof text, "%.17g", v);
        const std::string expected = "attribute '" + attribute + "': " + text + (unit.empty() ? "" : " " + unit) +
                                     " is out of range (expected " + range.at("text").get<std::string>() + ")";
        return diagnostics.joined().find(expected) != std::string::npos;
      };
      const auto range_error = [&](double v) {
        Diagnostics diagnostics;
        load_with(v, diagnostics);
        return diagnostics.joined().find("out of range") != std::string::npos;
      };
      const double step_hi = std::max(1e-9, std::abs(hi) * 1e-9), step_lo = std::max(1e-9, std::abs(lo) * 1e-9);
      // A whole number's neighbours are whole numbers.
      EXPECT_TRUE(refused(whole ? hi + 1 : hi + step_hi)) << attribute << " above " << hi;
      EXPECT_FALSE(range_error(hi)) << attribute << " at " << hi;
      if (range.at("min_exclusive").get<bool>()) {
        EXPECT_TRUE(refused(lo)) << attribute << " at its exclusive minimum " << lo;
        EXPECT_FALSE(range_error(lo + step_lo)) << attribute << " just above " << lo;
      } else {
        EXPECT_TRUE(refused(whole ? lo - 1 : lo - step_lo)) << attribute << " below " << lo;
        EXPECT_FALSE(range_error(lo)) << attribute << " at " << lo;
      }
    }
  }
}

TEST(SensorsCommand, TextNamesEveryElementAndAttribute) {
  const std::string text = sear_output("sensors");
  for (const DeviceKind* k : device_kinds()) {
    SCOPED_TRACE(k->element);
    const std::string head = std::string("<") + k->element + ">  " + k->summary + "\n";
    const auto at = text.find(head);
    ASSERT_NE(at, std::string::npos);
    EXPECT_TRUE(at == 0 || text[at - 1] == '\n');
    // The kind's block runs to the blank line that ends it.
    const std::string block = text.substr(at, text.find("\n\n", at) - at);
    std::vector<std::string> attributes = mount_attributes(k->mount);
    for (const DeviceWire& w : k->wires) attributes.emplace_back(w.attribute);
    for (const DeviceParam& p : k->params) attributes.emplace_back(p.attribute);
    for (const std::string& a : attributes) EXPECT_NE(block.find("\n    " + a + " "), std::string::npos) << a;
    for (const DeviceParam& p : k->params)
      for (const std::string& c : p.choices) EXPECT_NE(block.find(c), std::string::npos) << c;
  }
}

// docs/project.md's reference between the markers is the command's output, byte for byte; and that
// output has a section for every kind with a row for every attribute.
TEST(SensorsCommand, ProjectPageReferenceIsTheMarkdownOutput) {
  const std::string markdown = sear_output("sensors --markdown");
  for (const DeviceKind* k : device_kinds()) {
    SCOPED_TRACE(k->element);
    const auto at = markdown.find(std::string("\n#### `<") + k->element + ">`\n");
    ASSERT_NE(at, std::string::npos);
    const std::string section = markdown.substr(at + 1, markdown.find("\n#### ", at + 1) - at - 1);
    std::vector<std::string> attributes = mount_attributes(k->mount);
    for (const DeviceWire& w : k->wires) attributes.emplace_back(w.attribute);
    for (const DeviceParam& p : k->params) attributes.emplace_back(p.attribute);
    for (const std::string& a : attributes) EXPECT_NE(section.find("\n| `" + a + "` |"), std::string::npos) << a;
  }

  std::ifstream in(SEAR_DEVICE_REFERENCE, std::ios::binary);
  ASSERT_TRUE(in) << "cannot read " << SEAR_DEVICE_REFERENCE;
  std::ostringstream page;
  page << in.rdbuf();
  const std::string text = page.str();
  const std::string marker = "<!-- sear sensors --markdown -->", begin = marker + "\n", end = "<!-- end -->";
  const auto from = text.find(begin);
  ASSERT_NE(from, std::string::npos) << SEAR_DEVICE_REFERENCE << " has no line '" << marker << "'; add it and '" << end
                                     << "', then run scripts/update-device-reference.sh";
  const auto to = text.find(end, from + begin.size());
  ASSERT_NE(to, std::string::npos) << SEAR_DEVICE_REFERENCE << "'s reference has no '" << end << "' after it";
  EXPECT_EQ(text.substr(from + begin.size(), to - from - begin.size()), markdown)
      << SEAR_DEVICE_REFERENCE << "'s device reference differs from `sear sensors --markdown`: run "
      << "scripts/update-device-reference.sh";
}

}  // namespace
}  // namespace sear
