// A medium package of our own in the shape of Modelica.Media's: a partial
// base package whose function specificEnthalpy_pTX calls the specificEnthalpy
// and setState_pTX that a derived package redeclares, whose BaseProperties
// declares the ThermodynamicState that package extends, and whose constants
// (nX from substanceNames, substanceNames from mediumName, T0 from
// reference_T) take the values the most derived package's extends clause
// gives. Names in what a package inherits are looked up in that package
// (MLS 5.6.1, 7.1).
package Media
  partial package PartialMedium
    constant String mediumName = "unnamed";
    constant String substanceNames[:] = {mediumName};
    constant Integer nX = size(substanceNames, 1);
    constant Real reference_T = 298.15;
    type Temperature = Real(start = 288.15, nominal = 300, unit = "K");
    replaceable record ThermodynamicState
    end ThermodynamicState;
    replaceable partial model BaseProperties
      Real p;
      Temperature T;
      Real h;
      Real u;
      Real d;
      Real X[nX];
      ThermodynamicState state;
    equation
      X = fill(1 / nX, nX);
    end BaseProperties;
    replaceable partial function specificEnthalpy
      input ThermodynamicState state;
      output Real h;
    end specificEnthalpy;
    replaceable partial function setState_pTX
      input Real p;
      input Real T;
      input Real X[nX];
      output ThermodynamicState state;
    end setState_pTX;
    replaceable partial function setSmoothState
      input Real x;
      input ThermodynamicState state_a;
      input ThermodynamicState state_b;
      input Real x_small;
      output ThermodynamicState state;
    end setSmoothState;
    function specificEnthalpy_pTX
      input Real p;
      input Real T;
      input Real X[nX];
      output Real h;
    algorithm
      h := specificEnthalpy(setState_pTX(p, T, X));
    end specificEnthalpy_pTX;
  end PartialMedium;

  partial package PartialSimpleMedium
    extends PartialMedium;
    constant Real cp_const;
    constant Real cv_const;
    constant Real d_const;
    constant Real T0 = reference_T;
    redeclare record extends ThermodynamicState
      Real p;
      Temperature T;
    end ThermodynamicState;
    redeclare model extends BaseProperties
    equation
      h = specificEnthalpy_pTX(p, T, X);
      u = cv_const * (T - T0);
      d = d_const;
      state.T = T;
      state.p = p;
    end BaseProperties;
    redeclare function extends specificEnthalpy
    algorithm
      h := cp_const * (state.T - T0);
    end specificEnthalpy;
    redeclare function extends setState_pTX
    algorithm
      state := ThermodynamicState(p = p, T = T);
    end setState_pTX;
    redeclare function extends setSmoothState
    algorithm
      state := ThermodynamicState(p = smoothStep(x, state_a.p, state_b.p, x_small),
                                  T = smoothStep(x, state_a.T, state_b.T, x_small));
    end setSmoothState;
    function smoothStep "y1 above x_small, y2 below -x_small, a cubic between (as Modelica.Media.Common)"
      input Real x;
      input Real y1;
      input Real y2;
      input Real x_small;
      output Real y;
    algorithm
      y := smooth(1, if x > x_small then y1 else if x < -x_small then y2
                     else x / x_small * ((x / x_small)^2 - 3) * (y2 - y1) / 4 + (y1 + y2) / 2);
    end smoothStep;
  end PartialSimpleMedium;

  package Oil
    extends PartialSimpleMedium(mediumName = "oil", cp_const = 2000, cv_const = 1800, d_const = 850,
                                T0 = 273.15);
  end Oil;

  package Water
    extends PartialSimpleMedium(mediumName = "water", cp_const = 4184, cv_const = 4150, d_const = 1000,
                                T0 = 273.15);
  end Water;
end Media;

// A closed volume of oil heated at constant power, and a state that moves
// from a cold reference to the volume's state between t = 20 and 40 (as the
// MSL's SimpleLiquidWater example). The volume's temperature has the
// author's initial condition; the smoothed state's weight on it is 0 until
// t = 20, so that temperature, not the smoothed one that the model
// differentiates, must be the state.
model MediumVolume
  package Medium = Media.Oil;
  parameter Real V = 0.01 "volume, m3";
  parameter Real Q = 500 "heating power, W";
  Medium.BaseProperties medium(T(start = 300, fixed = true));
  Medium.ThermodynamicState cold = Medium.setState_pTX(1e5, 280, {1});
  Medium.ThermodynamicState mixed;
  Real m "mass, kg";
  Real U "internal energy, J";
  Real der_T "rate of the smoothed temperature";
  Real h_mixed = Medium.specificEnthalpy(mixed);
  Real n = Medium.nX;
equation
  medium.p = 1e5;
  m = medium.d * V;
  U = m * medium.u;
  der(U) = Q;
  mixed = Medium.setSmoothState(time - 30, medium.state, cold, 10);
  der_T = der(mixed.T);
end MediumVolume;

// A heated volume whose medium is a replaceable package, as Modelica.Fluid's
// components have: the functions and constants it reaches through `Medium`
// are those of the package a modifier puts in its place.
model HeatedVolume
  replaceable package Medium = Media.PartialMedium;
  parameter Real V = 0.01 "volume, m3";
  parameter Real Q = 500 "heating power, W";
  Medium.BaseProperties medium(T(start = 300, fixed = true));
  Real m = medium.d * V "mass, kg";
  Real h_pT = Medium.specificEnthalpy_pTX(1e5, medium.T, fill(1 / Medium.nX, Medium.nX));
  Real n = Medium.nX;
equation
  medium.p = 1e5;
  m * der(medium.u) = Q;
end HeatedVolume;

// Two of them with different media, and one whose medium its own class's
// extends clause redeclares.
model ReplacedMedia
  model OilVolume
    extends HeatedVolume(redeclare package Medium = Media.Oil);
  end OilVolume;
  OilVolume oil;
  HeatedVolume water(redeclare package Medium = Media.Water);
end ReplacedMedia;
