// delay() (MLS 3.7.2.4) in models of our own, each with a reference the
// test computes: test_delays.cpp.
package Delays
  // x' = -x(t - 1), x = 1 before t = 1: by the method of steps
  // x = 1 - t on [0, 1], 1 - t + (t - 1)^2/2 on [1, 2], minus (t - 2)^3/6 on [2, 3].
  model Steps
    Real x(start = 1, fixed = true);
  equation
    der(x) = -delay(x, 1);
  end Steps;

  // A step of u at t = 0.2 (a state event) reaches y exactly at 0.2 + T: a
  // time event, so the relation on y and the integral of y switch there.
  model DelayedStep
    parameter Real T = 0.5;
    Real u = if time > 0.2 then 1 else 0;
    output Real y = delay(u, T);
    Boolean late = y > 0.5;
    Real x(start = 0, fixed = true);
  equation
    der(x) = y;
  end DelayedStep;

  // Delays of expressions, nested and summed, for sensitivities: k scales
  // the whole right-hand side, a only the older term.
  model Feedback
    parameter Real k = 1;
    parameter Real a = 0.3;
    Real x(start = 1, fixed = true);
    Real y;
  equation
    y = a*delay(x, 0.7) + delay(delay(x*x, 0.4), 0.2);
    der(x) = -k*y;
  end Feedback;

  // A state event (x = 0.5, its time moves with k) doubles the gain g.
  // GainSwitch delays x, which does not jump there: its sensitivities go
  // through the event. DelayedSwitch delays g*x, which does: the delayed
  // jump 0.4 later moves with k too, and that is refused.
  model GainSwitch
    parameter Real k = 1;
    Real x(start = 1, fixed = true);
    discrete Real g(start = 1, fixed = true);
  equation
    der(x) = -k*g*delay(x, 0.4);
    when x < 0.5 then
      g = 2;
    end when;
  end GainSwitch;

  model DelayedSwitch
    parameter Real k = 1;
    Real x(start = 1, fixed = true);
    discrete Real g(start = 1, fixed = true);
  equation
    der(x) = -k*delay(g*x, 0.4);
    when x < 0.5 then
      g = 2;
    end when;
  end DelayedSwitch;

  // x' = -k x(t - 0.7): on [0, 0.7] x = 1 - k t, and on [0.7, 1.4]
  // x = 1 - 0.7 k - k (t - 0.7) + k^2 (t - 0.7)^2 / 2.
  model Linear
    parameter Real k = 1;
    Real x(start = 1, fixed = true);
  equation
    der(x) = -k*delay(x, 0.7);
  end Linear;

  // A steady start: at t0, delay(x) is x (MLS: x(t0) until t0 + T), so
  // der(x) = 0 gives x0 = u/k, and x stays there.
  model SteadyStart
    parameter Real u = 2;
    parameter Real k = 4;
    parameter Real T = 0.3;
    Real x;
  initial equation
    der(x) = 0;
  equation
    der(x) = u - k*delay(x, T, 1);
  end SteadyStart;

  // A lossless line between matched resistors (as the MSL's TLine1 writes
  // it): the far end sees half the source, TD later. v2 and i2 through the
  // delays of each other form an algebraic loop only across time.
  model Line
    parameter Real Z0 = 50;
    parameter Real TD = 0.1;
    Real vs = sin(10*time);
    Real v1, i1, i2, es, er;
    output Real v2;
  equation
    vs - v1 = Z0*i1;   // source resistor into port 1
    v2 = -Z0*i2;       // load resistor on port 2
    i1 = (v1 - es)/Z0;
    i2 = (v2 - er)/Z0;
    es = 2*delay(v2, TD) - delay(er, TD);
    er = 2*delay(v1, TD) - delay(es, TD);
  end Line;

  // A counter delayed and read back through integer(): constant pieces of
  // the history must come back exactly (3, not 2.9999...).
  model DelayedCount
    discrete output Integer n(start = 0, fixed = true);
    output Integer m;
  equation
    when sample(0.1, 0.1) then
      n = pre(n) + 1;
    end when;
    m = integer(delay(n, 0.05));
  end DelayedCount;

  // A delay time that varies: x' = -x(0.9 t - 1), x = 1 - t until
  // t = 10/9, then x' = -(2 - 0.9 t) while 0.9 t - 1 <= 10/9.
  model VaryingTime
    parameter Real k = 1;
    Real x(start = 1, fixed = true);
  equation
    der(x) = -k*delay(x, 1 + 0.1*time, 2);
  end VaryingTime;

  model VaryingWithoutMax
    Real x(start = 1, fixed = true);
  equation
    der(x) = -delay(x, 1 + 0.1*time);
  end VaryingWithoutMax;

  model ZeroTime
    parameter Real T = 0;
    Real x(start = 1, fixed = true);
  equation
    der(x) = -delay(x, T);
  end ZeroTime;
end Delays;
