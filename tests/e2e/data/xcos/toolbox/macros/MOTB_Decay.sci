// Interface function of the block MoToolbox.Decay (tests/e2e/data/xcos/toolbox):
// a Modelica block without ports, parameters tau and the start value of x.
function [x, y, typ] = MOTB_Decay(job, arg1, arg2)
    x = [];
    y = [];
    typ = [];
    select job
    case "set" then
        x = arg1;
        exprs = x.graphics.exprs;
        while %t do
            [ok, tau, x0, exprs] = scicos_getvalue("Set MOTB_Decay parameters", ..
                ["Time constant tau (s)"; "Initial value x0"], list("vec", 1, "vec", 1), exprs);
            if ~ok then
                break
            end
            x.model.rpar = [tau; x0];
            x.model.equations.parameters(2) = list(tau, x0);
            x.graphics.exprs = exprs;
            break
        end
    case "define" then
        tau = 1;
        x0 = 1;
        model = scicos_model();
        model.sim = "MoToolbox.Decay";
        model.blocktype = "c";
        model.dep_ut = [%t %f];
        model.rpar = [tau; x0];
        mo = modelica();
        mo.model = "MoToolbox.Decay";
        mo.inputs = [];
        mo.outputs = [];
        mo.parameters = list(["tau", "x"], list(tau, x0), [0, 1]);
        model.equations = mo;
        model.in = [];
        model.out = [];
        x = standard_define([2 2], model, string([tau; x0]), list([], 0));
    end
endfunction
