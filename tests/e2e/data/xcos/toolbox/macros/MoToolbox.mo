package MoToolbox "mocompile's test block library (tests/e2e/data/xcos/toolbox)"
  model Decay "First-order decay: der(x) = -x/tau, x(0) = x0"
    parameter Real tau = 1 "time constant";
    Real x(start = 1) "decaying quantity";
  equation
    der(x) = -x / tau;
  end Decay;
end MoToolbox;
