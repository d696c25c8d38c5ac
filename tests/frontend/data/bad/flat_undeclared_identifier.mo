// expect: unknown identifier `R1.v` in an equation of the flat class (Xcos flat dialect)
class flat_undeclared_identifier
	parameter Real `R1.R` = 100. "Resistance";
	Real `R1.i` "";
equation
	(`R1.R` * `R1.i`) = `R1.v`;
end flat_undeclared_identifier;
