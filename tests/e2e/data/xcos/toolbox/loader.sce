// mocompile's test block library MoToolbox, laid out like a toolbox that
// Scilab's toolbox manager (ATOMS) installed: <name>/<version>/loader.sce.
// Like Coselica's start script, it loads the blocks' interface functions and
// adds the folder of its Modelica library to %MODELICA_USER_LIBS.
mo_toolbox_root = get_absolute_file_path("loader.sce");
getd(mo_toolbox_root + "macros");
global %MODELICA_USER_LIBS;
%MODELICA_USER_LIBS = [%MODELICA_USER_LIBS; mo_toolbox_root + "macros"];
clear mo_toolbox_root;
