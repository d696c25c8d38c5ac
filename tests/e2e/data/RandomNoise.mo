// The random generators of ModelicaExternalC (ModelicaRandom.c), declared as
// Modelica.Math.Random declares them, and used as its noise blocks use them:
// a state seeded from parameters by a loop of xorshift64* steps (evaluated
// when the model is translated), then one xorshift128+ draw per sample.
package RandomNoise
  function xorshift64star
    input Integer stateIn[2];
    output Real result;
    output Integer stateOut[2];
    external "C" ModelicaRandom_xorshift64star(stateIn, stateOut, result);
  end xorshift64star;

  function xorshift128plus
    input Integer stateIn[4];
    output Real result;
    output Integer stateOut[4];
    external "C" ModelicaRandom_xorshift128plus(stateIn, stateOut, result);
  end xorshift128plus;

  function xorshift1024star
    input Integer stateIn[33];
    output Real result;
    output Integer stateOut[33];
    external "C" ModelicaRandom_xorshift1024star(stateIn, stateOut, result);
  end xorshift1024star;

  // Four Integers from two seeds: five xorshift64* steps, then two more for
  // the second half.
  function seeded
    input Integer localSeed;
    input Integer globalSeed;
    output Integer state[4];
  protected
    Real r;
    Integer s[2] = {localSeed, globalSeed};
  algorithm
    for i in 1:5 loop
      (r, s) := xorshift64star(s);
    end for;
    state[1:2] := s;
    (r, s) := xorshift64star(s);
    state[3:4] := s;
  end seeded;

  // r: a uniform number in (0, 1] drawn at every sample; x integrates it.
  model SampledNoise
    parameter Integer seed = 5;
    parameter Integer globalSeed = 67867967;
    parameter Real period = 0.1;
    discrete Integer state[4];
    discrete Real r;
    Real x(start = 0, fixed = true);
  initial equation
    pre(state) = seeded(seed, globalSeed);
    r = xorshift128plus(pre(state));
  equation
    when sample(period, period) then
      (r, state) = xorshift128plus(pre(state));
    end when;
    der(x) = r;
  end SampledNoise;

  // xorshift1024*'s 33 Integers (16 words and an index) drawn at samples.
  model LongStateNoise
    parameter Integer first = 3;
    discrete Integer state[33];
    discrete Real r(start = 0, fixed = true);
  initial equation
    pre(state) = cat(1, {first + i for i in 1:32}, {0});
  equation
    when sample(0.25, 0.25) then
      (r, state) = xorshift1024star(pre(state));
    end when;
  end LongStateNoise;

  // The impure generator: a hidden xorshift1024* state that
  // setInternalState stores and impureRandom steps at every call (as the
  // MSL's Math.Random.Utilities and its GlobalSeed use them).
  function setInternalState
    input Integer[33] rngState;
    input Integer id;
    external "C" ModelicaRandom_setInternalState_xorshift1024star(rngState, size(rngState, 1), id);
  end setInternalState;

  function initializeImpure
    input Integer seed;
    output Integer id;
  algorithm
    id := seed;
    setInternalState(cat(1, {seed + i for i in 1:32}, {0}), id);
  end initializeImpure;

  function impureRandom
    input Integer id;
    output Real y;
    external "C" y = ModelicaRandom_impureRandom_xorshift1024star(id);
  end impureRandom;

  // `first`: the first number, drawn when the model is translated; y: the
  // next ones, at initialisation and at t = 0.5, 1, ... The when-clause comes
  // before the initialisation in the flattening order.
  model ImpureDraws
    parameter Integer seed = 11;
    final parameter Integer id(fixed = false);
    final parameter Real first(fixed = false);
    discrete Real y;
  equation
    when {initial(), sample(0.5, 0.5)} then
      y = impureRandom(id);
    end when;
  initial equation
    id = initializeImpure(seed);
    first = impureRandom(id);
  end ImpureDraws;

  // Two draws in one clause: y1, y2 = the next two numbers at each sample.
  model ImpureTwice
    parameter Integer seed = 11;
    final parameter Integer id(fixed = false);
    discrete Real y1;
    discrete Real y2;
  initial equation
    id = initializeImpure(seed);
  equation
    when sample(0.5, 0.5) then
      y1 = impureRandom(id);
      y2 = impureRandom(id);
    end when;
  end ImpureTwice;

  // Three draws in one clause: refused (each draw repeats the state before).
  model ImpureThrice
    parameter Integer seed = 11;
    final parameter Integer id(fixed = false);
    discrete Real y[3];
  initial equation
    id = initializeImpure(seed);
  equation
    when sample(0.5, 0.5) then
      y[1] = impureRandom(id);
      y[2] = impureRandom(id);
      y[3] = impureRandom(id);
    end when;
  end ImpureThrice;

  // Draws in two clauses: refused.
  model ImpureTwoClauses
    extends ImpureTwice;
    discrete Real y3;
  equation
    when sample(0.25, 0.5) then
      y3 = impureRandom(id);
    end when;
  end ImpureTwoClauses;

  // A declaration that does not match ModelicaRandom.h: refused.
  function wrongSize
    input Integer stateIn[3];
    output Real result;
    output Integer stateOut[3];
    external "C" ModelicaRandom_xorshift128plus(stateIn, stateOut, result);
  end wrongSize;

  model WrongStateSize
    discrete Integer state[3](each start = 1, each fixed = true);
    discrete Real r;
  equation
    when sample(0.1, 0.1) then
      (r, state) = wrongSize(pre(state));
    end when;
  end WrongStateSize;
end RandomNoise;
