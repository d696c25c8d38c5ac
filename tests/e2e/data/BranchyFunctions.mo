package BranchyFunctions "Functions that branch on their own intermediate values"
  function stages "n rounds of a map that branches on its own value; each round reads s three times"
    input Real x;
    input Real a;
    input Integer n = 14;
    output Real s;
  algorithm
    s := x;
    for i in 1:n loop
      if s < 0.5 then
        s := a*s*(1 - s) + 0.1*x;
      else
        s := 0.25*a + 0.1*x - 0.3*(s - 0.5)*(s + 0.2) "meets the other branch at s = 0.5";
      end if;
    end for;
  end stages;

  function secant "(sin u - sin v)/(u - v), refined, where the branch guards the division"
    input Real u;
    input Real v;
    output Real q;
  protected
    Real d;
  algorithm
    d := u - v;
    if abs(d) > 1e-3 then
      q := (sin(u) - sin(v))/d;
      for i in 1:5 loop
        q := q + 0.01*q*(1 - q*q);
      end for;
    else
      q := cos((u + v)/2);
      for i in 1:5 loop
        q := q + 0.01*q*(1 - q*q);
      end for;
    end if;
  end secant;

  model Stages
    parameter Real a = 2.5;
    Real x(start = 0, fixed = true);
    Real y;
    Real z(start = 0, fixed = true);
  equation
    der(x) = 0.3 "x up to 1.2: s stays in [0, 1]";
    y = stages(x, a);
    der(z) = y;
  end Stages;

  model Secant
    parameter Real k = 1;
    Real u(start = 0, fixed = true);
    Real q;
    Real w(start = 0, fixed = true);
  equation
    der(u) = k*cos(time);
    q = secant(u, 0);
    der(w) = q;
  end Secant;
end BranchyFunctions;
