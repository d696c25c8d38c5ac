// The MSL's own table blocks (needs Modelica 3.2.2 on the library path), with
// closed forms: t is a periodic triangle, h a linear time table with a start
// time, a time scale and an offset (x integrates its second column: x = t
// before 0.3, then t + 5 (t - 0.3) + (t - 0.3)^2/4), m a 1-D table of 3 t.y
// continued beyond its end, m2 a bilinear 2-D table (= t.y + 0.5).
model MslTables
  Modelica.Blocks.Sources.CombiTimeTable t(table = [0, 0; 1, 1; 2, 0],
    extrapolation = Modelica.Blocks.Types.Extrapolation.Periodic);
  Modelica.Blocks.Sources.CombiTimeTable h(table = [0, 0, 5; 1, 1, 6; 2, 0, 7], startTime = 0.3,
    offset = {1}, timeScale = 2);
  Modelica.Blocks.Tables.CombiTable1Ds m(table = [0, 0; 1, 1; 2, 4]);
  Modelica.Blocks.Tables.CombiTable2D m2(table = [0, 0, 1; 0, 0, 1; 1, 1, 2]);
  Real x(start = 0, fixed = true);
  output Real triangle = t.y[1];
  output Real m_y = m.y[1];
  output Real m2_y = m2.y;
equation
  m.u = 3 * t.y[1];
  m2.u1 = t.y[1];
  m2.u2 = 0.5;
  der(x) = h.y[2];
end MslTables;
