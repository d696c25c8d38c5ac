// Evaluate = true on a record parameter covers its fields, as the MSL's Spice3
// devices declare `parameter ModelcardMOS modelcard annotation(Evaluate = true)`
// and compute their internal nodes' capacitances from it. Here the junction's
// capacitance card.Cj = 0 must drop der(vj): vj is an algebraic node
// (vj = v*Rl/(R + Rl)), not a state of a singular system, and the derived record
// `junction` (bound to an expression of the card, Evaluate too) folds as well.
// Exact: v = exp(-t/(C*(R + Rl))).
package EvaluatedCard
  record Card
    parameter Real C = 1 "main capacitance";
    parameter Real Cj = -1e40 "junction capacitance, -1e40: not given";
    parameter Real R = 1;
    parameter Real Rl = 3;
  end Card;

  record Junction
    parameter Real Cj;
    parameter Real G;
  end Junction;

  model Circuit
    parameter Card card(Cj = 0, C = 0.5) annotation(Evaluate = true);
    final parameter Junction junction = Junction(Cj = if card.Cj > -1e40 then card.Cj else 1e-3, G = 1/card.Rl)
      annotation(Evaluate = true);
    Real v(start = 1, fixed = true) "capacitor voltage";
    Real vj "junction node";
    Real i;
  equation
    card.C*der(v) = -i;
    i*card.R = v - vj;
    junction.Cj*der(vj) = i - vj*junction.G;
  end Circuit;
end EvaluatedCard;
