#include "schema_command.hpp"

#include <linx/schema.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <stdexcept>
#include <vector>

#include "cli_common.hpp"
#include "io/input_file.hpp"
#include "io/output_file.hpp"
#include "io/suggestion.hpp"

namespace linx::cli {

void addSchemaOptions(CLI::App& cmd, SchemaOptions& options) {
  std::string names;
  for (const schema::Record& r : schema::records())
    names += fmt::format("{}{}", names.empty() ? "" : ", ", r.name);
  cmd.add_option("records", options.records, "Records to print (default all): " + names);
  cmd.add_option("--docs", options.docs,
                 "Rewrite the tables of this Markdown file between its <!-- schema: NAME --> "
                 "and <!-- /schema --> markers");
}

int schema(const SchemaOptions& options) {
  if (!options.docs.empty()) {
    std::string text;
    try {
      text = io::readInputFile(options.docs, io::kSceneLimit, "a Markdown file");
      io::writeFileAtomically(options.docs, schema::updateTables(text));
    } catch (const std::exception& e) {
      throw BadInput(fmt::format("{}: {}", options.docs, e.what()));
    }
    return 0;
  }
  std::vector<const schema::Record*> chosen;
  for (const std::string& name : options.records) {
    const schema::Record* r = schema::findRecord(name);
    if (!r) {
      std::vector<std::string> names;
      for (const schema::Record& known : schema::records()) names.push_back(known.name);
      const std::string_view closest = io::closestName(name, names);
      throw BadInput(
          fmt::format("'{}': no such record{}", name,
                      closest.empty() ? "" : fmt::format(" (did you mean {}?)", closest)));
    }
    chosen.push_back(r);
  }
  if (chosen.empty())
    for (const schema::Record& r : schema::records()) chosen.push_back(&r);
  for (std::size_t i = 0; i < chosen.size(); ++i)
    fmt::print("{}## {}\n\n{}", i == 0 ? "" : "\n", chosen[i]->name,
               schema::markdownTable(*chosen[i]));
  return 0;
}

}  // namespace linx::cli
