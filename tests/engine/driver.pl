% Runs every q/3 of queries.pl in SWI-Prolog and prints its solutions or its error kind.
:- initialization(main, main).
main :- forall(q(N, T, G), run(N, T, G)).
run(N, T, G) :-
    catch(( findall(T, G, L), format("~w ok ~q~n", [N, L]) ),
          E,
          ( E = error(Kind, _), compound(Kind) -> functor(Kind, K, _), format("~w error ~w~n", [N, K])
          ; E = error(Kind, _) -> format("~w error ~w~n", [N, Kind])
          ; format("~w error other~n", [N]) )).
