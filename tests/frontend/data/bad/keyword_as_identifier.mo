// expect: syntax error: keyword 'equation' used as a component name
model keyword_as_identifier
  Real equation;
equation
  equation = time;
end keyword_as_identifier;
