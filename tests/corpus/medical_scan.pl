% expect: plan scan_day
% expect: warn W0009
% A scanning sequence: a patient is registered, prepared, scanned (durative) and reviewed.
% `discharge` forgets every room a patient was in with an open `del`, as SWI-Prolog's delete/3.
patient(ann). patient(bob).
room(prep). room(scanner).
action(register(P), [arrived(P)], [registered(P)], [], [patient(P)], [add(registered(P)), add(at(P, prep))]).
action(scan_start(P), [registered(P), at(P, prep), scanner_free], [scanned(P)], [], [],
    [del(scanner_free), del(at(P, prep)), add(at(P, scanner)), add(scanning(P))]).
action(scan_end(P), [scanning(P)], [], [], [], [del(scanning(P)), add(scanned(P)), add(scanner_free)]).
action(review(P), [scanned(P)], [reviewed(P)], [], [], [add(reviewed(P))]).
action(discharge(P), [reviewed(P)], [], [], [], [del(at(P, _)), add(home(P))]).
duration(scan(_), 10, 20).
scan_day :- go([arrived(ann), arrived(bob), scanner_free], [home(ann), home(bob)]).
