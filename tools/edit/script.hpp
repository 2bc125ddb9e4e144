#pragma once
// Scripts for `cmr edit --script FILE`: one command per line, words separated
// by blanks, '#' starts a comment. Mouse positions are window pixels (row 0
// at the top) unless a command says world coordinates. Every command runs
// through the editor's real input handlers or named actions, between frames
// of the real window; the script's pointer is also the panels' mouse (a press
// over a panel goes to its widgets, not to the canvas).
//
//   mouse X Y                 move the cursor (drags and pans follow it)
//   press left|right|middle [shift]   mouse button down at the cursor
//   release left|right|middle          mouse button up
//   scroll DY [shift]         zoom about the cursor (DY > 0: closer); with
//                             shift over a point: scale its weight by 1.1^DY
//   key NAME [ctrl]           a key: z/y with ctrl undo/redo, c, d, a, g, f,
//                             x (fix), s (snap)
//   drag K X Y [STEPS]        press on point K, move to world (X, Y) in STEPS
//                             frames (default 10), release
//   select K | group K... | all on|off | mode cmr|cmrwi | depth D
//   shading on|off | split S|none | chain on|off | comb on|off
//   segments A..B|A|all       which segments the region and verdicts judge
//   ui on|off | overlay on|off          panels / curve and points drawn
//   view X0 Y0 X1 Y1 | fit              world rectangle of the window
//   weight K W                the weight of point K (clamped to 1e-3..1e3)
//   weight-region on|off      the panel's strip of the selected weight's region
//   knot I U                  move knot I to U
//   drag-knot I U [STEPS]     the pointer drags knot I's handle on the ruler
//                             to U in STEPS frames (default 10), as a user does
//   insert U [TIMES] | remove U [TOL] | elevate | clamp | uniform
//                             knot operations; a refused one (a removal
//                             beyond TOL) is reported on stderr, nothing changes
//   kcurve points|modify|off  κ-curve mode: clicks (press left) add points;
//                             modify: the cubic chain, handles in G1 pairs
//   closed on|off             the κ-curve closed (points stage)
//   undo | redo
//   resize W H                the window to W x H (the swapchain is recreated)
//   save PATH | screenshot PATH
//   export-region PATH        the region as `cmr region` computes it for the
//                             window's view and size (.png: --png, else --labels)
//   export-view PATH          the next presented frame as a PNG (the panel's
//                             "export PNG" button)
//   fix                       bezierize/fix's nearest certified fix of the
//                             view's requirement (Editor::fix_curve), animated;
//                             the status line (what moved, or why no fix) on stderr
//   snap                      the selected point to the nearest certified
//                             position of its region (Editor::snap_selected)
//   type x|y|w TEXT           the pointer clicks into the panel's field, types
//                             TEXT and presses Enter (typed coordinates)
//   legend                    the legend's lines on stderr (kind, colour, words)
//   fit-region | show-point K on|off | comb-size S | graph kappa|abs|log
//   contour K | glyph X | save-all      several curves (sources.hpp)
//   constrain on|off          keep a dragged point in its region
//   status                    the selected point and the status line, on stderr
//   wait N                    render N frames
//   quit
// In the orbit view of a space curve (orbit.hpp), besides the generic mouse,
// press, release, wait, resize, screenshot, export-view and quit:
//   orbit YAW PITCH | zoom F | pan DX DY     the camera (degrees, factor, pixels)
//   plane region|screen|xy|yz|zx              the plane a dragged point moves in
//   drag K A B [STEPS]        to plane coordinates (A, B) of K's plane
//   select K | fit | comb on|off | ui on|off | scroll DY | key f|x|c [ctrl]
//   fix | undo | redo | status | legend | save [PATH]
// Any other command is refused there with one line.
#include <filesystem>
#include <string>
#include <vector>

namespace cmr::edit {

struct ScriptCommand {
  std::string name;
  std::vector<std::string> args;
  int line = 0;
};

/// Parses a script; throws InputError ("FILE:LINE: ...") for an unknown
/// command or a wrong number of words.
std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& source);
std::vector<ScriptCommand> read_script(const std::filesystem::path& path);

/// Argument i as a number / integer / on|off; InputError naming the line.
double number_arg(const ScriptCommand& c, std::size_t i);
int int_arg(const ScriptCommand& c, std::size_t i);
bool switch_arg(const ScriptCommand& c, std::size_t i);

}  // namespace cmr::edit
