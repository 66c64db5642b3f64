// `sylva verify [RECIPE] [--node NODE]... [--update-refs] [-j N] [--report-dir DIR]`: the
// reference-image check as a command (docs/stages/verify.md).
//
//  1. Loads the recipe and picks its `verify` nodes (all, or those named by --node).
//  2. Builds what they need through the engine and the cache (like `sylva build --target`).
//  3. Runs the verification core itself, outside the cache, for each node: the current binary
//     always renders (a cached verdict could predate a renderer change), and the reports are
//     written whether the views pass or not, to <out>/<recipe>/verify-reports/<node>/
//     (report.html, report.json, junit.xml, the renderings and heat maps).
//  4. With --update-refs, copies the renderings of every view that failed, had no reference, or
//     had an unreadable one into the node's references directory.
//
// Prints one line per view that did not pass (stderr) and, per node, the verdict and the path
// of report.html (stdout). Exit codes: 0 every view passed (or was updated); 1 a view failed,
// the build failed, or no headless OpenGL; 2 usage or recipe error; 130 interrupted.
#pragma once

#include <memory>

#include "app/cli.h"

namespace sylva {
std::unique_ptr<CliCommand> make_verify_command();
}
