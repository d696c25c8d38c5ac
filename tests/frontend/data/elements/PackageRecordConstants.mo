// Package constants of record type, as Modelica.Media's gas data: declared
// with modifiers of their fields (the other fields take the record's
// defaults, which may read the fields before them), bound by an extends
// modifier in the package that uses them, read field by field (`data.R`,
// `Gases.N2.a[2]`, in a function too), and an array of them with `each`
// modifiers, indexed (`fluids[2].Tc`).
model PackageRecordConstants
  record Data
    String name;
    Real MM;
    Real R = 8.314 / MM;
    Real a[3] = {1, 2, 3};
  end Data;
  record Fluid
    Real Tc = 100;
    Real pc;
  end Fluid;
  package Gases
    constant Data N2(name = "N2", MM = 0.028, a = {4, 5, 6});
    constant Data O2(name = "O2", MM = 0.032);
  end Gases;
  partial package Gas
    constant Data data;
    constant Real R = data.R;
    constant Fluid fluids[2](each pc = 3e6);
    function cp
      input Real T;
      output Real y;
    algorithm
      y := data.a[1] + data.a[2] * T;
    end cp;
  end Gas;
  package N2
    extends Gas(data = Gases.N2);
  end N2;
  package O2
    extends Gas(data = Gases.O2);
  end O2;
  Real rn = N2.R;
  Real ro = O2.data.R;
  Real a2 = Gases.N2.a[2];
  Real cn = N2.cp(time);
  Real co = O2.cp(time);
  Real tc = N2.fluids[2].Tc;
  Real pc = O2.fluids[1].pc;
end PackageRecordConstants;
