// `extends Base(redeclare T x(...))`: the replaceable component takes the new
// type; the original declaration's modifiers (offset) stay, the
// redeclaration's (k) and the ones from further out (x.offset) apply on top.
model RedeclareComponentInExtends
  partial block Source
    parameter Real offset = 0;
    output Real y;
  end Source;
  block Const
    extends Source;
    parameter Real k = 1;
  equation
    y = offset + k;
  end Const;
  block Ramp
    extends Source;
    parameter Real rate = 1;
  equation
    y = offset + rate * time;
  end Ramp;
  model Driven
    parameter Real v0 = 0.5;
    replaceable Source src(offset = v0);
    Real x(start = 0, fixed = true);
  equation
    der(x) = src.y - x;
  end Driven;
  model WithConst
    parameter Real K = 3;
    extends Driven(redeclare Const src(k = K));
  end WithConst;
  WithConst a;
  WithConst b(v0 = 1, src(k = 4));
  Driven c(redeclare Ramp src(rate = 2));
end RedeclareComponentInExtends;
