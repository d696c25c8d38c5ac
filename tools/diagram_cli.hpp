// The command-line options of diagram input, shared by mocompile and morun
// (header-only: the tools link CLI11, the pipeline library does not).
#pragma once

#include <CLI/CLI.hpp>

#include "xcos_diagram.hpp"

namespace mo::tools {

/// Adds --scilab-lib, --scilab-timeout, --init-fixed, --open-loop and --save-flat to `app`.
inline void add_diagram_options(CLI::App& app, DiagramOptions& options) {
  app.add_option("--scilab-lib", options.libraries,
                 "Diagram input: folder of a Scilab block library the diagram uses, e.g. Coselica "
                 "(an installed toolbox with loader.sce, or its source folder) (repeatable; also "
                 "MO_SCILAB_LIBS=DIR[:DIR...]; toolboxes installed with Scilab's ATOMS load by themselves)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--scilab-timeout", options.timeout_seconds,
                 "Diagram input: stop Scilab after this many seconds")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_flag("--init-fixed", options.init_fixed,
               "Diagram input: apply the fixed = true flags of Scilab's init file (<title>_imf_init.xml) as "
               "Modelica's initialisation does (by default start values only, as Scilab's simulation)");
  app.add_flag("--open-loop", options.open_loop,
               "Diagram input: leave the diagram's non-Modelica blocks out; the inputs they drive stay "
               "inputs of the model (by default the supported blocks are translated to Modelica, "
               "docs/xcos-dialect.md)");
  app.add_option("--save-flat", options.save_dir,
                 "Diagram input: also keep the files Scilab wrote (<title>_imf.mo, <title>_imf_init.xml, "
                 "...) in this folder");
}

}  // namespace mo::tools
