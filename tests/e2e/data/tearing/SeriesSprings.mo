// Two springs in series with a massless joint between them, as MultiBody's
// ThreeSprings connects two line-force springs. The spring class declares
// its length with start = 0 (as the MSL's PartialCompliant declares s_rel):
// that is the class's default, not a guess of this model's author, who
// gives the joint's position one. Tearing iterates on the joint; each
// length follows from it. The pair pulls a point mass like one spring of
// stiffness c1 c2/(c1 + c2) and rest length L1 + L2 (EquivalentSpring).
package SeriesSprings
  model Spring "a line spring from a to b"
    parameter Real c "stiffness";
    parameter Real L "rest length";
    Real a[2];
    Real b[2];
    Real s(start = 0) "length";
    Real f "tension";
    Real e[2] "unit vector from a to b";
  equation
    s = sqrt((b - a)*(b - a));
    f = c*(s - L);
    e = (b - a)/max(s, 1e-10);
  end Spring;

  model TwoInSeries
    parameter Real m = 0.8;
    parameter Real g = 9.81;
    Spring spring1(c = 20, L = 0.1);
    Spring spring2(c = 40, L = 0.1);
    Real b[2](start = {0.5, -0.3}, each fixed = true) "mass";
    Real v[2](each start = 0, each fixed = true);
    Real p[2](start = {0.2, -0.2}) "massless joint";
  equation
    spring1.a = {0, 0};
    spring1.b = p;
    spring2.a = p;
    spring2.b = b;
    zeros(2) = -spring1.f*spring1.e + spring2.f*spring2.e;
    der(b) = v;
    m*der(v) = -spring2.f*spring2.e - {0, m*g};
  end TwoInSeries;

  // TwoInSeries with the joint's start left out: no author's guess, so
  // Cellier's heuristic alone chooses, and takes the lengths first (they are
  // in the most equations); the joint position, torn after them, makes them
  // explicit, so they are dropped again.
  model TwoInSeriesUnguessed
    parameter Real m = 0.8;
    parameter Real g = 9.81;
    Spring spring1(c = 20, L = 0.1);
    Spring spring2(c = 40, L = 0.1);
    Real b[2](start = {0.5, -0.3}, each fixed = true);
    Real v[2](each start = 0, each fixed = true);
    Real p[2];
  equation
    spring1.a = {0, 0};
    spring1.b = p;
    spring2.a = p;
    spring2.b = b;
    zeros(2) = -spring1.f*spring1.e + spring2.f*spring2.e;
    der(b) = v;
    m*der(v) = -spring2.f*spring2.e - {0, m*g};
  end TwoInSeriesUnguessed;

  model EquivalentSpring
    parameter Real c = 20*40/(20 + 40);
    parameter Real L = 0.2;
    parameter Real m = 0.8;
    parameter Real g = 9.81;
    Real b[2](start = {0.5, -0.3}, each fixed = true);
    Real v[2](each start = 0, each fixed = true);
    Real s;
  equation
    s = sqrt(b*b);
    der(b) = v;
    m*der(v) = -c*(s - L)*b/s - {0, m*g};
  end EquivalentSpring;
end SeriesSprings;
