// Makes tests/e2e/data/xcos/BlockLoop.zcos and Scilab's own simulation of it,
// BlockLoop_scilab.csv: a first-order plant written in Modelica (MBLOCK
// Plant: 0.5 der(x) = u - x, y = x) in a loop of standard Scicos blocks that
// mocompile translates to Modelica (docs/xcos-dialect.md):
//   set point  sp = CURV_f(t) + |GENSIN_f(t)|         (BIGSOM_f, ABS_VALUE)
//   error      e  = sp - y                            (SUMMATION [1;-1])
//   relay      r  = HYSTHERESIS(e): 1 above 0.1, -1 below -0.1, at the crossings
//   drive      u  = SATURATION(GAINBLK(2) r / CONST_m(0.5) + RAMP + STEP_FUNCTION)
//                   (PRODUCT [1;-1], BIGSOM_f, limits +-2.5)
// A scope-like sink (TOWS_c on a CLOCK_c, every 0.01 s) also reads y: mocompile ignores it.
// Run: MO_OUT=DIR xvfb-run -a scilab -nw -nb -f make_block_loop.sce < /dev/null
mode(-1);
lines(0);
loadXcosLibs();
loadScicos();

function blk = mo_place(blk, x, y)
    blk.graphics.orig = [x, y];
endfunction

function lnk = mo_link(fb, fp, tb, tp)
    lnk = scicos_link(xx=[0; 0], yy=[0; 0], ct=[1, 1], from=[fb, fp, 0], to=[tb, tp, 1]);
endfunction

function lnk = mo_event(fb, fp, tb, tp)
    lnk = scicos_link(xx=[0; 0], yy=[0; 0], ct=[5, -1], from=[fb, fp, 0], to=[tb, tp, 1]);
endfunction

plant_txt = ["model Plant"; "  parameter Real tau = 0.5;"; "  Real x(start = 0);"; "  Real u;"; "  Real y;";
             "equation"; "  tau*der(x) = u - x;"; "  y = x;"; "end Plant;"];
plant = MBLOCK("define");
plant.graphics.exprs.in = sci2exp(["u"]);
plant.graphics.exprs.intype = sci2exp(["E"]);
plant.graphics.exprs.out = sci2exp(["y"]);
plant.graphics.exprs.outtype = sci2exp(["E"]);
plant.graphics.exprs.param = sci2exp(["tau"]);
plant.graphics.exprs.paramv = list("0.5");
plant.graphics.exprs.pprop = sci2exp([0]);
plant.graphics.exprs.nameF = "Plant";
plant.graphics.exprs.funtxt = plant_txt;
plant_mo = modelica();
plant_mo.model = "Plant";
plant_mo.inputs = "u";
plant_mo.outputs = "y";
plant_mo.parameters = list(["tau"], list(0.5), [0]);
plant.model.equations = plant_mo;
plant.model.sim = list("Plant", 30004);
plant.model.in = 1;
plant.model.out = 1;
plant.model.rpar = 0.5;
plant.graphics.in_implicit = "E";
plant.graphics.out_implicit = "E";
plant.graphics.pin = 0;
plant.graphics.pout = 0;

curv = CURV_f("define");                 // set point curve
curv.model.rpar = [0; 1; 2; 3; 0; 1; 0.5; 0.5; 0; 0; 3; 1];
curv.model.ipar = [4; 2; 10; 2; 10];
sine = GENSIN_f("define");
sine.graphics.exprs = ["0.2"; "6"; "0"];
absv = ABS_VALUE("define");
sum1 = BIGSOM_f("define");               // sp = curve + |sine|
err = SUMMATION("define");               // e = sp - y
hyst = HYSTHERESIS("define");
hyst.graphics.exprs = ["0.1"; "-0.1"; "1"; "-1"; "1"];
gain = GAINBLK("define");
gain.graphics.exprs(1) = "2";
cst = CONST_m("define");
cst.graphics.exprs = "0.5";
prod = PRODUCT("define");                // 2 r / 0.5
ramp = RAMP("define");
ramp.graphics.exprs = ["0.5"; "0.2"; "0"];
step = STEP_FUNCTION("define");          // 0 -> 1 at t = 1
sum2 = BIGSOM_f("define");               // ramp + step
sum3 = BIGSOM_f("define");               // relay part + sum2
sat = SATURATION("define");
sat.graphics.exprs = ["2.5"; "-2.5"; "1"];
split = SPLIT_f("define");
split.model.out = [-1; -1; -1];
tows = TOWS_c("define");
tows.graphics.exprs = ["1000"; "mo_y"; "0"];
tows.model.ipar = [1000; 4; ascii("mo_y")'];
clk = CLOCK_c("define");
for k = 1:size(clk.model.rpar.objs)
    o = clk.model.rpar.objs(k);
    if typeof(o) == "Block" then
        if o.gui == "EVTDLY_c" then
            o.graphics.exprs = ["0.01"; "0"];
            o.model.rpar = [0.01; 0];
            o.model.firing = 0;
            clk.model.rpar.objs(k) = o;
        end
    end
end

scs_m = scicos_diagram();
scs_m.props.title = "BlockLoop";
scs_m.props.tf = 3;
scs_m.props.tol = [1e-10; 1e-8; 1e-10; 100001; 0; 100; 0];
blocks = list(plant, curv, sine, absv, sum1, err, hyst, gain, cst, prod, ramp, step, sum2, sum3, sat, split, tows, clk);
for k = 1:size(blocks)
    scs_m.objs(k) = mo_place(blocks(k), 60 * k, 100);
end
// 1 plant 2 curv 3 sine 4 abs 5 sum1 6 err 7 hyst 8 gain 9 cst 10 prod
// 11 ramp 12 step 13 sum2 14 sum3 15 sat 16 split 17 tows 18 clk
links = list(mo_link(2, 1, 5, 1), mo_link(3, 1, 4, 1), mo_link(4, 1, 5, 2), ..
             mo_link(5, 1, 6, 1), mo_link(1, 1, 16, 1), mo_link(16, 1, 6, 2), mo_link(16, 2, 17, 1), ..
             mo_link(6, 1, 7, 1), mo_link(7, 1, 8, 1), mo_link(8, 1, 10, 1), mo_link(9, 1, 10, 2), ..
             mo_link(11, 1, 13, 1), mo_link(12, 1, 13, 2), mo_link(10, 1, 14, 1), mo_link(13, 1, 14, 2), ..
             mo_link(14, 1, 15, 1), mo_link(15, 1, 1, 1), mo_event(18, 1, 17, 1));
for k = 1:size(links)
    scs_m.objs(size(blocks) + k) = links(k);
end
xcosDiagramToScilab(getenv("MO_OUT") + "/BlockLoop.zcos", scs_m);

// Scilab's own simulation of the saved diagram, compiled as Xcos does and
// run with scicosim from 0 to each output time (every 0.01 s; a fresh run
// each time, as the corpus' event models were recorded: interrupting one run
// at the output times perturbs the relay): y is the Modelica block's state,
// the first entry of the state vector.
// (The blocks' variables go first: `prod` above hides Scilab's prod(), which
// the blocks' interface functions call.)
clear plant curv sine absv sum1 err hyst gain cst prod ramp step sum2 sum3 sat split tows clk blocks links o;
importXcosDiagram(getenv("MO_OUT") + "/BlockLoop.zcos");
[cpr, ok] = xcos_compile(scs_m);
tol = scs_m.props.tol;
fd = mopen(getenv("MO_OUT") + "/BlockLoop_scilab.csv", "wt");
mfprintf(fd, "time,y\n");
for k = 1:300
    state = cpr.state;
    [state, t] = scicosim(state, 0, k * 0.01, cpr.sim, "start", tol);
    [state, t] = scicosim(state, 0, k * 0.01, cpr.sim, "run", tol);
    mfprintf(fd, "%.17g,%.17g\n", k * 0.01, state.x(1));
    [state, t] = scicosim(state, t, t, cpr.sim, "finish", tol);
end
mclose(fd);
exit(0);
