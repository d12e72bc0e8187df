// Text that reaches an output language is data, never code: one quoting rule per language that
// linx writes (docs/reliability.md, "Output languages"). Every name, file name or message that
// comes from a scene, a run folder or the command line goes through one of these on its way out.
#pragma once

#include <string>
#include <string_view>

namespace linx::io {

/// The text as a terminal shows it without acting on any of it: valid UTF-8 is kept; NUL is
/// shown as `\0`, newline, carriage return and tab as `\n`, `\r`, `\t`, other control characters
/// (C0, DEL) and bytes that are not UTF-8 as `\xNN`, and the C1 controls, the bidirectional
/// overrides and isolates and the line and paragraph separators as `\uNNNN`. The result holds no
/// byte below 0x20 and no 0x7f, so it is one line; visible(visible(t)) == visible(t).
std::string visible(std::string_view text);

/// The text as a gnuplot double-quoted string literal, shown as visible() shows it: every byte
/// but ASCII letters, digits and ` .,:;_-+=()/` is written as an octal escape `\ooo`, so the
/// literal holds no quote, backslash, backquote (command substitution), `@` (macro expansion),
/// `$` or `%` that gnuplot could act on, and ends the line it is on.
std::string gnuplotString(std::string_view text);

/// The text for a POV-Ray `//` comment: visible(text), which holds no line end (a newline or a
/// carriage return would end the comment and make the rest POV-Ray code).
std::string povComment(std::string_view text);

/// The text as a POV-Ray string literal: visible(text) with `"` and `\` escaped.
std::string povString(std::string_view text);

}  // namespace linx::io
