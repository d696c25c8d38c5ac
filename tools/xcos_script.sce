// mocompile's Scilab script: compiles an Xcos diagram the way Xcos does
// (importXcosDiagram, xcos_compile), without a window, and stops once
// Scilab's Modelica translator (modelicat) has written the flat model: the
// C code generator modelicac is replaced by a function that records that.
//
// Everything comes from the environment and from files in the private work
// folder MO_XCOS_WORK; nothing of the diagram or of a path is pasted into
// Scilab code. The work folder receives:
//   status.txt  first line ok | missing-blocks | no-modelica | unsafe-name | error,
//               then details
//   out/        the files the translator wrote (<title>_im.mo, <title>_imf.mo, ...)
//               and translator_libs.txt: the Modelica files and folders the
//               translator read (those of Scilab's TMPDIR copied beside it)
//   done        written last: mocompile stops Scilab once it exists
// Input files: diagram.zcos or diagram.xcos (MO_XCOS_DIAGRAM names it),
// libraries.txt (one block-library folder a line, maybe empty).
mode(-1);
lines(0);
funcprot(0);
mo_work = getenv("MO_XCOS_WORK");

// The compile ends in a modal message box, which would block a windowless run.
function r = messagebox(varargin)
    r = 1;
    for k = 1:size(varargin)
        a = varargin(k);
        if type(a) == 10 then
            mprintf("messagebox: %s\n", strcat(a, " "));
        end
    end
endfunction

// Called by compile_modelica right after the translator succeeded.
function ok = modelicac(varargin)
    mputl("translated", getenv("MO_XCOS_WORK") + "/translated");
    ok = %f;
endfunction

// The diagram's regular (non-Modelica) blocks and their links, as the
// compiler sees them once the Modelica blocks are gathered into one block
// (c_pass1): written to out/blocks.txt for mocompile, which translates the
// blocks it knows into Modelica (tools/xcos_blocks.hpp has the format).
// Called by build_modelica_block below, so the variables of c_pass1 (nr,
// blklst, corinv, cmat, ccmat) are those of its caller. Numbers only, and
// names checked to be plain identifiers.
function mo_write_numbers(fd, tag, v)
    if type(v) <> 1 | ~isreal(v) then
        mfprintf(fd, "%s -1\n", tag);
        return;
    end
    v = v(:);
    mfprintf(fd, "%s %d", tag, size(v, "*"));
    for i = 1:size(v, "*")
        mfprintf(fd, " %.17g", v(i));
    end
    mfprintf(fd, "\n");
endfunction

function n = mo_plain_name(n)
    if type(n) <> 10 then
        n = "?";
    elseif size(n, "*") <> 1 then
        n = "?";
    elseif isempty(regexp(n, "/^[A-Za-z_][A-Za-z0-9_]*$/")) then
        n = "?";
    end
endfunction

function mo_dump_blocks(file, nreg, blocks, paths, links, events, diagram, nin, nout)
    fd = mopen(file, "wt");
    mfprintf(fd, "mo-xcos-blocks 1\nmodelica %d %d %d\n", nreg + 1, nin, nout);
    for k = 1:nreg
        b = blocks(k);
        o = diagram(scs_full_path(paths(k)));
        s = b.sim;
        if type(s) == 15 then
            s = s(1);
        end
        mfprintf(fd, "block %d %s %s\n", k, mo_plain_name(o.gui), mo_plain_name(s));
        mo_write_numbers(fd, "in", b.in);
        mo_write_numbers(fd, "out", b.out);
        mo_write_numbers(fd, "evtin", size(b.evtin, "*"));
        mo_write_numbers(fd, "nzcross", b.nzcross);
        mo_write_numbers(fd, "nmode", b.nmode);
        mo_write_numbers(fd, "rpar", b.rpar);
        mo_write_numbers(fd, "ipar", b.ipar);
        if type(b.opar) == 15 & size(b.opar) == 1 then
            mo_write_numbers(fd, "opar", b.opar(1));
        else
            mfprintf(fd, "opar -1\n");
        end
        mo_write_numbers(fd, "firing", b.firing);
        mo_write_numbers(fd, "state", b.state);
        mo_write_numbers(fd, "dstate", b.dstate);
    end
    for k = 1:size(links, 1)
        mfprintf(fd, "link %d %d %d %d\n", links(k, 1), links(k, 2), links(k, 3), links(k, 4));
    end
    for k = 1:size(events, 1)
        mfprintf(fd, "event %d %d %d %d\n", events(k, 1), events(k, 2), events(k, 3), events(k, 4));
    end
    mfprintf(fd, "end\n");
    mclose(fd);
endfunction

mo_build_modelica_block = build_modelica_block;
function [model, ok] = build_modelica_block(blklstm, corinvm, cmmat, NiM, NoM, NvM, scs_m, path)
    try
        mo_dump_blocks(getenv("MO_XCOS_WORK") + "/out/blocks.txt", nr, blklst, corinv, cmat, ccmat, scs_m, NiM, NoM);
    catch
        mprintf("mocompile: listing the diagram''s blocks failed: %s\n", lasterror());
    end
    if getenv("MO_XCOS_MODE", "") == "blocks" then
        model = [];
        ok = %f;
        return;
    end
    [model, ok] = mo_build_modelica_block(blklstm, corinvm, cmmat, NiM, NoM, NvM, scs_m, path);
endfunction

// The Modelica files and folders the translator reads (as translator.sci
// builds its -lib list), one a line in out/translator_libs.txt: mocompile
// flattens <title>_im.mo with them to check the init file's fixed flags.
mo_translator = translator;
function ok = translator(filemo, Mblocks, libs, Flat)
    try
        [mo_paths, mo_dir] = getModelicaPath();
        used = [];
        for k = 1:size(Mblocks, "r")
            funam = stripblanks(Mblocks(k));
            [d, n, e] = fileparts(funam);
            if e == ".mo" then
                used = [used; funam];
            else
                used = [used; mo_dir + funam + ".mo"];
            end
        end
        folders = pathconvert(libs, %f, %t);
        for k = 1:size(folders, "*")
            used = [used; folders(k)];
        end
        // Files in Scilab's TMPDIR (a generic block's model) go when Scilab
        // exits: copied to out/ and listed by name.
        out = getenv("MO_XCOS_WORK") + "/out/";
        tmp = pathconvert(TMPDIR, %t, %t);
        for k = 1:size(used, "*")
            if part(used(k), 1:length(tmp)) == tmp & isfile(used(k)) then
                [d, n, e] = fileparts(used(k));
                copyfile(used(k), out + n + e);
                used(k) = n + e;
            end
        end
        mputl(used, out + "translator_libs.txt");
    catch
        mprintf("mocompile: listing the translator''s libraries failed: %s\n", lasterror());
    end
    ok = mo_translator(filemo, Mblocks, libs, Flat);
endfunction

function mo_finish(status)
    w = getenv("MO_XCOS_WORK");
    mputl(status, w + "/status.txt");
    mputl("done", w + "/done");
endfunction

// A block library folder: an installed (built) toolbox has loader.sce,
// executed by the caller; in a source folder, the folders holding .sci files
// (loaded with getd by the caller: functions defined in a function would
// vanish with it) and those holding .mo files (Modelica libraries).
function [loader, sci_dirs, mo_dirs] = mo_library(d)
    loader = "";
    sci_dirs = [];
    mo_dirs = [];
    if isfile(d + "/loader.sce") then
        loader = d + "/loader.sce";
        return;
    end
    pending = d;
    while size(pending, "*") > 0
        dir = pending(1);
        pending(1) = [];
        if findfiles(dir, "*.sci") <> [] then
            sci_dirs = [sci_dirs; dir];
        end
        if findfiles(dir, "*.mo") <> [] then
            mo_dirs = [mo_dirs; dir];
        end
        entries = findfiles(dir);
        for k = 1:size(entries, "*")
            if isdir(dir + "/" + entries(k)) then
                pending = [pending; dir + "/" + entries(k)];
            end
        end
    end
endfunction

// The interface functions of every block and the Modelica models of the
// Modelica blocks, superblocks included (a walk with a stack, no recursion).
function [guis, models] = mo_blocks(diagram)
    guis = [];
    models = [];
    stack = list(diagram);
    while size(stack) > 0
        d = stack(1);
        stack(1) = null();
        for k = 1:size(d.objs)
            o = d.objs(k);
            if typeof(o) <> "Block" then
                continue;
            end
            guis = [guis; o.gui];
            if typeof(o.model.rpar) == "diagram" then
                stack($ + 1) = o.model.rpar;
            end
            if typeof(o.model.equations) == "modelica" then
                models = [models; o.model.equations.model];
            end
        end
    end
endfunction

// The toolboxes found in the install folders of Scilab's toolbox manager
// (ATOMS): SCIHOME/atoms/<name>/<version>/ (a user's install) and
// SCI/contrib/<name>/<version>/ (all users), those with a loader.sce; of a
// toolbox with several versions, the last in sorted order. Toolboxes already
// loaded are skipped. Found from the folders, not from ATOMS's database, so a
// toolbox unpacked there by hand is found too.
function loaders = mo_atoms_loaders()
    loaders = [];
    roots = [SCIHOME + "/atoms"; SCI + "/contrib"];
    for r = 1:size(roots, "*")
        if ~isdir(roots(r)) then
            continue;
        end
        names = gsort(findfiles(roots(r)), "g", "i");
        for n = 1:size(names, "*")
            loaded = %f;
            try
                loaded = atomsIsLoaded(names(n));
            catch
            end
            if loaded | ~isdir(roots(r) + "/" + names(n)) then
                continue;
            end
            versions = gsort(findfiles(roots(r) + "/" + names(n)), "g", "d");
            for v = 1:size(versions, "*")
                candidate = roots(r) + "/" + names(n) + "/" + versions(v) + "/loader.sce";
                if isfile(candidate) then
                    loaders = [loaders; candidate];
                    break;
                end
            end
        end
    end
endfunction

function missing = mo_missing(guis)
    missing = [];
    for k = 1:size(guis, "*")
        if ~isdef(guis(k)) then
            missing = [missing; guis(k)];
        end
    end
    missing = unique(missing);
endfunction

// Scilab's translator runs a shell command holding the title and the
// Modelica model names: only plain names go through.
function ok = mo_plain(names)
    ok = %t;
    for k = 1:size(names, "*")
        if isempty(regexp(names(k), "/^[A-Za-z_][A-Za-z0-9_.]*$/")) then
            ok = %f;
        end
    end
endfunction

function title = mo_safe_title(title)
    title = strsubst(stripblanks(title), "/[^A-Za-z0-9_]/", "_", "r");
    if title == "" then
        title = "diagram";
    end
    if ~isempty(regexp(title, "/^[0-9]/")) then
        title = "_" + title;
    end
endfunction

status = "error";
try
    loadXcosLibs();
    loadScicos();
    libraries = mgetl(mo_work + "/libraries.txt");
    for k = 1:size(libraries, "*")
        if libraries(k) == "" then
            continue;
        end
        [mo_loader, mo_sci_dirs, mo_mo_dirs] = mo_library(libraries(k));
        if mo_loader <> "" then
            exec(mo_loader, -1);
        end
        for j = 1:size(mo_sci_dirs, "*")
            getd(mo_sci_dirs(j));
        end
        global %MODELICA_USER_LIBS;
        %MODELICA_USER_LIBS = [%MODELICA_USER_LIBS; mo_mo_dirs];
    end
    if ~importXcosDiagram(mo_work + "/" + getenv("MO_XCOS_DIAGRAM")) then
        error("Scilab could not read the diagram");
    end
    [guis, models] = mo_blocks(scs_m);
    if mo_missing(guis) <> [] then
        // Toolboxes installed with Scilab's toolbox manager (ATOMS), loaded
        // here at the top level so that their functions stay defined.
        try
            mo_installed = atomsGetInstalled();
            if mo_installed <> [] then
                atomsLoad(unique(mo_installed(:, 1)));
            end
        catch
            mprintf("mocompile: loading the ATOMS toolboxes failed: %s\n", lasterror());
        end
    end
    if mo_missing(guis) <> [] then
        // Toolboxes in ATOMS's install folders that its database does not
        // list (or that atomsLoad could not load), loaded here at the top level.
        mo_loaders = mo_atoms_loaders();
        for k = 1:size(mo_loaders, "*")
            mprintf("mocompile: loading the toolbox %s\n", mo_loaders(k));
            try
                exec(mo_loaders(k), -1);
            catch
                mprintf("mocompile: loading %s failed: %s\n", mo_loaders(k), lasterror());
            end
        end
    end
    missing = mo_missing(guis);
    if getenv("MO_XCOS_MODE", "") == "blocks" then
        // Only the blocks and links (out/blocks.txt), as Xcos compiles the
        // diagram (context, each block's parameters evaluated, first pass),
        // stopped before the Modelica part is translated. A block whose
        // interface function is missing (a Modelica block of a library that
        // is not installed) keeps the model stored in the diagram: its
        // stand-in returns the block unchanged.
        for k = 1:size(missing, "*")
            if mo_plain(missing(k)) & isempty(strindex(missing(k), ".")) then
                deff("[x, y, typ] = " + missing(k) + "(job, arg1, arg2)", "x = arg1; y = []; typ = [];");
            end
        end
        scs_m.props.title(1) = mo_safe_title(scs_m.props.title(1));
        try
            [cpr, ok] = xcos_compile(scs_m);
        catch
            mprintf("mocompile: xcos_compile stopped: %s\n", lasterror());
        end
        if isfile(mo_work + "/out/blocks.txt") then
            status = "ok";
        else
            status = ["error"; "Scilab did not list the diagram''s blocks"];
        end
    elseif missing <> [] then
        status = ["missing-blocks"; missing];
    elseif models == [] then
        status = "no-modelica";
    elseif ~mo_plain(models) then
        status = ["unsafe-name"; "a Modelica block names a model that is not a plain Modelica name"];
    else
        scs_m.props.title(1) = mo_safe_title(scs_m.props.title(1));
        try
            [cpr, ok] = xcos_compile(scs_m);
        catch
            mprintf("mocompile: xcos_compile stopped: %s\n", lasterror());
        end
        files = [findfiles(TMPDIR, "*_im*"); findfiles(TMPDIR, "*.err")];
        for k = 1:size(files, "*")
            copyfile(TMPDIR + "/" + files(k), mo_work + "/out/" + files(k));
        end
        if isfile(mo_work + "/translated") then
            status = "ok";
        else
            status = ["error"; "Scilab''s Modelica translator did not write a flat model"];
        end
    end
catch
    status = ["error"; lasterror()];
end
mo_finish(status);
exit(0);
