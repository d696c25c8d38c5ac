// Makes the test diagrams SeriesRLC.zcos and SeriesRLC.xcos (the same, as
// plain XML) of tests/e2e/data/xcos from Scilab's own blocks: a series RLC
// circuit (Electrical palette) driven through a controlled voltage source
// (CVS) by a constant block (CONST_m, not Modelica): mocompile makes that
// signal an input of the model. Also NoModelica.zcos, FixedInit.zcos and
// ToolboxDecay.zcos (below).
// Run: MO_OUT=DIR MO_TOOLBOX=toolbox xvfb-run -a scilab -nw -nb -f make_diagrams.sce < /dev/null
mode(-1);
lines(0);
loadXcosLibs();
loadScicos();

// Block `blk` at (x, y) with parameter expressions `exprs` (evaluated by Xcos at compile).
function blk = mo_place(blk, x, y)
    blk.graphics.orig = [x, y];
    blk.graphics.sz = [40, 40];
endfunction

// Link from port `fp` of block `fb` (fk: 0 output, 1 input) to port `tp` of block `tb`.
function lnk = mo_link(fb, fp, fk, tb, tp, tk, implicit)
    if implicit then
        ct = [1, 2];
    else
        ct = [1, 1];
    end
    lnk = scicos_link(xx=[0; 0], yy=[0; 0], ct=ct, from=[fb, fp, fk], to=[tb, tp, tk]);
endfunction

scs_m = scicos_diagram();
scs_m.props.title = "SeriesRLC";
scs_m.props.tf = 1;

src = CONST_m("define");      // 1: the drive signal (a regular Xcos block)
src.graphics.exprs = "1";
src.model.rpar = [];
src.model.opar = list(1);
cvs = CVS("define");          // 2: controlled voltage source
res = Resistor("define");     // 3
res.graphics.exprs = "10";
res.model.rpar = 10;
res.model.equations.parameters(2) = list(10);
ind = Inductor("define");     // 4
ind.graphics.exprs = "0.1";
ind.model.rpar = 0.1;
ind.model.equations.parameters(2) = list(0.1);
cap = Capacitor("define");    // 5
cap.graphics.exprs = ["0.001"; "0"];
cap.model.rpar = [0.001; 0];
cap.model.equations.parameters(2) = list(0.001, 0);
spl = IMPSPLIT_f("define");   // 6
gnd = Ground("define");       // 7

blocks = list(src, cvs, res, ind, cap, spl, gnd);
for k = 1:size(blocks)
    scs_m.objs(k) = mo_place(blocks(k), 60 * k, 100);
end
links = list(mo_link(1, 1, 0, 2, 1, 1, %f), ..  // CONST_m → CVS control input
             mo_link(2, 2, 1, 3, 1, 1, %t), ..  // CVS.p — R.p
             mo_link(3, 1, 0, 4, 1, 1, %t), ..  // R.n — L.p
             mo_link(4, 1, 0, 5, 1, 1, %t), ..  // L.n — C.p
             mo_link(5, 1, 0, 6, 1, 1, %t), ..  // C.n — split
             mo_link(6, 1, 0, 2, 1, 0, %t), ..  // split — CVS.n
             mo_link(6, 2, 0, 7, 1, 1, %t));    // split — ground
// Scilab 6 connects the ports when a link between existing blocks is added.
for k = 1:size(links)
    scs_m.objs(size(blocks) + k) = links(k);
end
xcosDiagramToScilab(getenv("MO_OUT") + "/SeriesRLC.zcos", scs_m);
xcosDiagramToScilab(getenv("MO_OUT") + "/SeriesRLC.xcos", scs_m);  // the same, plain XML
// NoModelica.zcos: one constant block and nothing of Modelica (mocompile refuses it).
scs_m = scicos_diagram();
scs_m.props.title = "NoModelica";
scs_m.objs(1) = mo_place(CONST_m("define"), 60, 100);
xcosDiagramToScilab(getenv("MO_OUT") + "/NoModelica.zcos", scs_m);
// FixedInit.zcos: a Modelica generic block (MBLOCK, Scilab's Modelica
// palette) FixedLag: der(x) = -x, y = 2 x; x is a state with start 0
// (parameter property 1), y a fixed state with start 4 (property 2): only the
// translator's init file says that y is fixed, so x(0) = 2.
fl_txt = ["model FixedLag"; "  Real x;"; "  Real y;"; "equation"; "  der(x) = -x;"; "  y = 2*x;"; "end FixedLag;"];
fl = MBLOCK("define");
fl.graphics.exprs.in = "[]";
fl.graphics.exprs.intype = "[]";
fl.graphics.exprs.out = "[]";
fl.graphics.exprs.outtype = "[]";
fl.graphics.exprs.param = sci2exp(["x"; "y"]);
fl.graphics.exprs.paramv = list("0", "4");
fl.graphics.exprs.pprop = sci2exp([1; 2]);
fl.graphics.exprs.nameF = "FixedLag";
fl.graphics.exprs.funtxt = fl_txt;
fl_mo = modelica();
fl_mo.model = "FixedLag";
fl_mo.inputs = [];
fl_mo.outputs = [];
fl_mo.parameters = list(["x", "y"], list(0, 4), [1, 2]);
fl.model.equations = fl_mo;
fl.model.sim = list("FixedLag", 30004);
fl.model.in = [];
fl.model.out = [];
fl.model.rpar = [0; 4];
fl.graphics.in_implicit = [];
fl.graphics.out_implicit = [];
fl.graphics.pin = [];
fl.graphics.pout = [];
scs_m = scicos_diagram();
scs_m.props.title = "FixedInit";
scs_m.props.tf = 1;
scs_m.objs(1) = mo_place(fl, 60, 100);
xcosDiagramToScilab(getenv("MO_OUT") + "/FixedInit.zcos", scs_m);
// ToolboxDecay.zcos: the block MOTB_Decay of the test block library
// MoToolbox (folder toolbox/, MO_TOOLBOX), tau = 0.5, x0 = 2.
exec(getenv("MO_TOOLBOX") + "/loader.sce", -1);
dec = MOTB_Decay("define");
dec.graphics.exprs = ["0.5"; "2"];
dec.model.rpar = [0.5; 2];
dec.model.equations.parameters(2) = list(0.5, 2);
scs_m = scicos_diagram();
scs_m.props.title = "ToolboxDecay";
scs_m.props.tf = 1;
scs_m.objs(1) = mo_place(dec, 60, 100);
xcosDiagramToScilab(getenv("MO_OUT") + "/ToolboxDecay.zcos", scs_m);
mputl("done", getenv("MO_OUT") + "/made");
exit(0);
