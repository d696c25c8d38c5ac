// Two masses joined by a spring-damper whose relative position and velocity
// are preferred as states, written as the MSL 3.2.2 writes its compliant
// elements: v_rel = der(s_rel), and der(v_rel) nowhere. The second mass's
// s and v are always states (as MassWithStopAndFriction's) and it bounces
// off a stop at smax, where s2 and v2 are reinitialised. Which variables
// are states decides what the reinit keeps: with s_rel and v_rel states
// (as other Modelica tools choose them) the spring's stretch and rate are
// continuous and the first mass jumps with the second.
package StopBehindSpring
  model Written
    parameter Real c = 100 "spring constant";
    parameter Real d = 5 "damping";
    parameter Real F = 20 "push on the first mass";
    parameter Real L0 = 0.5 "unstretched length";
    parameter Real smax = 0.1 "stop";
    Real s1(start = -0.5, fixed = true), v1(start = 0, fixed = true);
    Real s2(start = 0, fixed = true, stateSelect = StateSelect.always);
    Real v2(start = 0, fixed = true, stateSelect = StateSelect.always);
    Real s_rel(stateSelect = StateSelect.prefer), v_rel(stateSelect = StateSelect.prefer);
    Real f "spring-damper force on the second mass";
  equation
    v1 = der(s1);
    der(v1) = F - f;
    v2 = der(s2);
    der(v2) = f;
    s_rel = s2 - s1;
    v_rel = der(s_rel);
    f = -c*(s_rel - L0) - d*v_rel;
    when s2 >= smax then
      reinit(s2, smax);
      reinit(v2, -0.5*v2);
    end when;
  end Written;

  model WithAcceleration "the same, with der(v_rel) written out"
    extends Written;
    Real a_rel;
  equation
    a_rel = der(v_rel);
  end WithAcceleration;

  model Unpreferable "v_rel is preferred, but an input-free algebraic x cannot be a state"
    extends Written;
    Real x(stateSelect = StateSelect.prefer);
  equation
    x = if time < 0.5 then 1 else 2;
  end Unpreferable;
end StopBehindSpring;
