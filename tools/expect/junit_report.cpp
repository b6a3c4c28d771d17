#include "expect/junit_report.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <stdexcept>
#include <tuple>

namespace sear {
namespace {

// XML 1.0 allows only some characters (tab, newline and from U+0020 on, less surrogates and
// U+FFFE/U+FFFF); tinyxml2 writes whatever bytes it is given. A console log is whatever the
// firmware printed, so everything else becomes U+FFFD before it goes into the report: invalid
// UTF-8, control characters, '\r' (which parsers read back as '\n'). In attributes, tab and
// newline become spaces, as any XML parser would read them. By hand: none of our libraries
// replaces invalid UTF-8, and iconv can only drop it.
std::string xml_safe(const std::string& in, bool attribute) {
  static const char kReplacement[] = "\xEF\xBF\xBD";
  std::string out;
  out.reserve(in.size());
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(in[i]); };
  for (std::size_t i = 0; i < in.size();) {
    const unsigned char b = byte(i);
    if (b < 0x80) {
      if (b == '\t' || b == '\n') out.push_back(attribute ? ' ' : static_cast<char>(b));
      else if (b < 0x20 || b == 0x7F) out += kReplacement;
      else out.push_back(static_cast<char>(b));
      ++i;
      continue;
    }
    const std::size_t length = b >= 0xF0 ? 4 : b >= 0xE0 ? 3 : b >= 0xC0 ? 2 : 0;
    std::uint32_t code = length == 4 ? b & 0x07u : length == 3 ? b & 0x0Fu : b & 0x1Fu;
    bool ok = length != 0 && b < 0xF5 && i + length <= in.size();
    for (std::size_t k = 1; ok && k < length; ++k) {
      ok = (byte(i + k) & 0xC0) == 0x80;
      code = code << 6 | (byte(i + k) & 0x3Fu);
    }
    // Overlong forms, surrogates, U+FFFE/U+FFFF and beyond U+10FFFF are not characters XML takes.
    static const std::uint32_t kLeast[] = {0, 0, 0x80, 0x800, 0x10000};
    ok = ok && code >= kLeast[length] && code <= 0x10FFFF && !(code >= 0xD800 && code <= 0xDFFF) &&
         code != 0xFFFE && code != 0xFFFF;
    if (ok) {
      out.append(in, i, length);
      i += length;
    } else {
      out += kReplacement;
      ++i;
    }
  }
  return out;
}

std::string xml_seconds(std::int64_t ns) {
  const std::int64_t ms = (ns + 500000) / 1000000;
  return fmt::format("{}.{:03d}", ms / 1000, ms % 1000);
}


[[noreturn]] void bad_report(const std::string& path, const tinyxml2::XMLElement* at, const std::string& what) {
  throw std::runtime_error(fmt::format("{}:{}: not a SEAR JUnit report: {}", path, at ? at->GetLineNum() : 0, what));
}

std::int64_t parse_seconds(const std::string& path, const tinyxml2::XMLElement& e) {
  const char* text = e.Attribute("time");
  const std::string t = text ? text : "";
  const auto dot = t.find('.');
  const bool ok = dot != std::string::npos && dot > 0 && t.size() - dot - 1 == 3 &&
                  t.find_first_not_of("0123456789.") == std::string::npos && t.find('.', dot + 1) == std::string::npos;
  if (!ok) bad_report(path, &e, fmt::format("time '{}' is not seconds with three decimals", t));
  return std::stoll(t.substr(0, dot)) * 1000000000 + std::stoll(t.substr(dot + 1)) * 1000000;
}

std::string text_of(const tinyxml2::XMLElement* e) { return e && e->GetText() ? e->GetText() : ""; }

}  // namespace

std::string JunitSuite::name() const { return fmt::format("{} (seed {})", scenario, seed); }

JunitSuite junit_suite(const Scenario& scenario, std::uint64_t seed, const ExpectationChecker& checker,
                       std::int64_t end_ns, std::string system_out) {
  JunitSuite s;
  s.scenario = scenario.name;
  s.scenario_file = scenario.file;
  s.project_file = scenario.project_file;
  s.seed = seed;
  s.time_ns = end_ns;
  s.system_out = std::move(system_out);
  for (const ExpectationResult& r : checker.results()) {
    JunitCase c;
    c.name = r.expectation->name;
    c.time_ns = r.verdict == Verdict::Pending ? end_ns : r.time_ns;
    if (r.verdict != Verdict::Passed) {
      c.failed = true;
      c.message = r.verdict == Verdict::Pending ? "undecided when the run ended" : r.seen;
      c.detail = fmt::format("{}\nwritten at {}:{}", r.verdict == Verdict::Pending ? c.message : failure_text(r),
                             r.expectation->source.file, r.expectation->source.line);
    }
    s.cases.push_back(std::move(c));
  }
  return s;
}

void write_junit(const std::string& path, std::vector<JunitSuite> suites) {
  std::stable_sort(suites.begin(), suites.end(), [](const JunitSuite& a, const JunitSuite& b) {
    return std::tie(a.scenario, a.seed, a.scenario_file) < std::tie(b.scenario, b.seed, b.scenario_file);
  });
  tinyxml2::XMLDocument doc;
  doc.InsertEndChild(doc.NewDeclaration());  // version 1.0, UTF-8
  auto* root = doc.NewElement("testsuites");
  doc.InsertEndChild(root);
  std::size_t tests = 0, failures = 0, errors = 0;
  std::int64_t time_ns = 0;
  const auto attribute = [](tinyxml2::XMLElement* e, const char* name, const std::string& value) {
    e->SetAttribute(name, xml_safe(value, true).c_str());
  };
  root->SetAttribute("name", "sear");
  for (const JunitSuite& s : suites) {
    const std::size_t failed = static_cast<std::size_t>(
        std::count_if(s.cases.begin(), s.cases.end(), [](const JunitCase& c) { return c.failed; }));
    const std::size_t count = s.cases.size() + (s.error.empty() ? 0 : 1);
    const std::size_t errored = s.error.empty() ? 0 : 1;
    tests += count;
    failures += failed;
    errors += errored;
    time_ns += s.time_ns;
    auto* suite = root->InsertNewChildElement("testsuite");
    attribute(suite, "name", s.name());
    attribute(suite, "tests", std::to_string(count));
    attribute(suite, "failures", std::to_string(failed));
    attribute(suite, "errors", std::to_string(errored));
    attribute(suite, "skipped", "0");
    attribute(suite, "time", xml_seconds(s.time_ns));
    auto* properties = suite->InsertNewChildElement("properties");
    for (const auto& [name, value] : {std::pair<const char*, std::string>{"scenario", s.scenario_file},
                                      {"project", s.project_file},
                                      {"seed", std::to_string(s.seed)}}) {
      auto* p = properties->InsertNewChildElement("property");
      attribute(p, "name", name);
      attribute(p, "value", value);
    }
    if (!s.error.empty()) {
      auto* c = suite->InsertNewChildElement("testcase");
      attribute(c, "classname", s.scenario);
      attribute(c, "name", "run");
      attribute(c, "time", xml_seconds(s.time_ns));
      auto* e = c->InsertNewChildElement("error");
      attribute(e, "message", s.error);
      attribute(e, "type", "run");
      e->SetText(xml_safe(s.error, false).c_str());
    }
    for (const JunitCase& k : s.cases) {
      auto* c = suite->InsertNewChildElement("testcase");
      attribute(c, "classname", s.scenario);
      attribute(c, "name", k.name);
      attribute(c, "time", xml_seconds(k.time_ns));
      if (!k.failed) continue;
      auto* f = c->InsertNewChildElement("failure");
      attribute(f, "message", k.message);
      attribute(f, "type", "expectation");
      f->SetText(xml_safe(k.detail, false).c_str());
    }
    if (!s.system_out.empty()) suite->InsertNewChildElement("system-out")->SetText(xml_safe(s.system_out, false).c_str());
  }
  root->SetAttribute("tests", std::to_string(tests).c_str());
  root->SetAttribute("failures", std::to_string(failures).c_str());
  root->SetAttribute("errors", std::to_string(errors).c_str());
  root->SetAttribute("time", xml_seconds(time_ns).c_str());
  if (doc.SaveFile(path.c_str()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error(fmt::format("{}: cannot write the JUnit report: {}", path, doc.ErrorStr()));
}

std::vector<JunitSuite> read_junit(const std::string& path) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error(fmt::format("{}:{}: cannot read the JUnit report: {}", path, doc.ErrorLineNum(),
                                         doc.ErrorStr()));
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "testsuites") bad_report(path, root, "its root is not <testsuites>");
  std::vector<JunitSuite> suites;
  for (auto* e = root->FirstChildElement("testsuite"); e; e = e->NextSiblingElement("testsuite")) {
    JunitSuite s;
    s.time_ns = parse_seconds(path, *e);
    bool has_seed = false;
    if (auto* properties = e->FirstChildElement("properties")) {
      for (auto* p = properties->FirstChildElement("property"); p; p = p->NextSiblingElement("property")) {
        const std::string name = p->Attribute("name") ? p->Attribute("name") : "";
        const std::string value = p->Attribute("value") ? p->Attribute("value") : "";
        if (name == "scenario") s.scenario_file = value;
        else if (name == "project") s.project_file = value;
        else if (name == "seed" && !value.empty() && value.find_first_not_of("0123456789") == std::string::npos) {
          s.seed = std::stoull(value);
          has_seed = true;
        }
      }
    }
    if (!has_seed) bad_report(path, e, "a <testsuite> has no seed property");
    for (auto* c = e->FirstChildElement("testcase"); c; c = c->NextSiblingElement("testcase")) {
      s.scenario = c->Attribute("classname") ? c->Attribute("classname") : "";
      if (auto* error = c->FirstChildElement("error")) {
        s.error = error->Attribute("message") ? error->Attribute("message") : "";
        continue;
      }
      JunitCase k;
      k.name = c->Attribute("name") ? c->Attribute("name") : "";
      k.time_ns = parse_seconds(path, *c);
      if (auto* f = c->FirstChildElement("failure")) {
        k.failed = true;
        k.message = f->Attribute("message") ? f->Attribute("message") : "";
        k.detail = text_of(f);
      }
      s.cases.push_back(std::move(k));
    }
    // A suite's name is "SCENARIO (seed N)"; with no test case it is the only place the scenario is.
    if (s.scenario.empty()) {
      const std::string name = e->Attribute("name") ? e->Attribute("name") : "";
      const std::string tail = fmt::format(" (seed {})", s.seed);
      if (name.size() >= tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0)
        s.scenario = name.substr(0, name.size() - tail.size());
    }
    s.system_out = text_of(e->FirstChildElement("system-out"));
    suites.push_back(std::move(s));
  }
  return suites;
}

void merge_junit(const std::vector<std::string>& inputs, const std::string& output) {
  std::vector<JunitSuite> all;
  for (const auto& input : inputs) {
    auto suites = read_junit(input);
    std::move(suites.begin(), suites.end(), std::back_inserter(all));
  }
  write_junit(output, std::move(all));
}

}  // namespace sear
