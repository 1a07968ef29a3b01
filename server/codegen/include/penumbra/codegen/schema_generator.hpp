#pragma once

// What proto/v1/common.schema.json restates of the C++ tables, for clients that cannot read C++:
// every setting of scene's table (kSettings: its kind as a JSON type, its range or names, its
// summary as the description; a setting that a state holds is required there, one the device
// bounds has the default limit as its maximum), the mode and frame-format names, the transfer
// function's preset names, position spaces, limits and defaults, the orbit's defaults (the default
// camera's) and the client message types (the request variant). The rest of the file is written by
// hand. proto/README.md's table of the client messages is written from their schemas the same way,
// hello.schema.json's mode capabilities from the kinds' name tables and its limits' defaults from
// the hello a server configured with nothing else sends, and the hello the web client's tests
// recorded from the server. update_schema writes these parts into the files
// (scripts/update-schema.sh) and SchemaAgreement.*IsGenerated fail while a committed file differs.

#include <penumbra/base/result.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace penumbra::codegen {

// `committed`, the text of common.schema.json, with its generated parts written from the tables,
// two-space indented as the file is; an error where the text is not a JSON object with `$defs`.
base::Result<std::string> generated_common_schema(std::string_view committed);

// `committed`, the text of proto/README.md, with the table between kTableBegin and kTableEnd
// written from the schemas in `schema_dir` (proto/v1) of the client message types, in the order of
// ClientMessage: each type, its members besides v, type and id (required ones marked, with their
// descriptions) and its schema's description; the limits tables' values (§8) as hello states them
// and the last cell of §5's `settings` and `output` rows as a new session's state holds them. An
// error where a marker or a schema is missing.
inline constexpr std::string_view kTableBegin =
        "<!-- The client messages: written from their schemas by scripts/update-schema.sh. -->";
inline constexpr std::string_view kTableEnd = "<!-- End of the client messages. -->";
base::Result<std::string> generated_readme(std::string_view committed,
                                           const std::filesystem::path& schema_dir);

// `committed`, the text of hello.schema.json, with the mode capabilities' names (technique,
// shadows, scattering, gradients) written from scene's name tables; an error where it is not an
// object.
base::Result<std::string> generated_hello_schema(std::string_view committed);

// `committed`, the text of the web client's recorded server messages
// (client_web/test/fixtures/server_messages.jsonl, one message a line, hello first), with the
// hello the server sends now (its modes, ranges, presets and limits at their defaults; the
// recorded renderer kept), and every recorded state as the server reports it now (the recorded
// values, a setting added since at a new state's value; a set's ack with the state it answers), so
// that the client's tests see the current tables. An error where the first line is not a hello or
// a recorded state is one the server no longer takes.
base::Result<std::string> generated_recorded_hello(std::string_view committed);

// The TypeScript module that gives the web client the server's names and views
// (client_web/src/protocol/generated/server_tables.ts): the formats frames are written in, the
// names of the settings' enums, the light types, the transfer function's position spaces, the
// mode table's kinds and the views (scene's name tables), each view's eye direction and up
// (scene::view_camera), the default camera's distance and field of view, every setting a state
// holds with its kind, range and summary (SETTINGS) and the state's TypeScript type
// (StateSettings), hello.limits' defaults and a new session's settings and output
// (scene::starting_frame through state_to_json). It is written whole: the client keeps no copy of
// its own.
inline constexpr std::string_view kClientTablesPath = "src/protocol/generated/server_tables.ts";
std::string generated_client_tables();

}  // namespace penumbra::codegen
