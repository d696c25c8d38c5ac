// Constant tables of a package indexed by signals (the MSL's Digital:
// `Tables.AndTable[auxiliary[i], x[i + 1]]` over the Logic enumeration):
// two varying subscripts nest two if-expressions; a constant subscript and a
// colon select a row; Integer() of an enumeration is its ordinal.
package LogicTables
  type Level = enumeration(low, high, unknown);
  constant Level AndTable[Level, Level] = [Level.low, Level.low, Level.low;
                                           Level.low, Level.high, Level.unknown;
                                           Level.low, Level.unknown, Level.unknown];
  constant Real Weights[2, 3] = [1, 2, 3; 4, 5, 6];
  // y: low until 0.5, unknown until 0.75, then high.
  model Gate
    Level a = if time < 0.5 then Level.low else Level.high;
    Level b = if time < 0.25 then Level.high elseif time < 0.75 then Level.unknown else Level.high;
    Level y = AndTable[a, b];
    Real w[3] = Weights[2, :];
    Real x(start = 0, fixed = true) "integrates the ordinal of y";
  equation
    der(x) = Integer(y);
  end Gate;
end LogicTables;
