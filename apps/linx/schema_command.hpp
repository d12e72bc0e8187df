// `linx schema [NAME...]`: the scene format's records as the docs' tables (linx/schema.hpp): what
// each field is, its bounds, default and meaning; `--docs FILE` rewrites the tables of a Markdown
// file between its `<!-- schema: NAME -->` and `<!-- /schema -->` markers.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace linx::cli {

struct SchemaOptions {
  std::vector<std::string> records;  ///< none: all
  std::string docs;                  ///< a Markdown file to rewrite, or empty
};

/// Adds the schema arguments to `cmd` (the `schema` subcommand).
void addSchemaOptions(CLI::App& cmd, SchemaOptions& options);
/// Prints the tables or rewrites options.docs; returns the exit status. Throws BadInput.
int schema(const SchemaOptions& options);

}  // namespace linx::cli
