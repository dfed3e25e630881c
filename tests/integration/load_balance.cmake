# Load balance with RVE migration (issue 5, item 4) and node-partition hostfiles (item 5).
set(_lb ${CMAKE_CURRENT_LIST_DIR}/load_balance.sh)
mpmdem_test(NAME load_balance_elastic COMMAND bash ${_lb} elastic TIMEOUT 300 SERIAL)
mpmdem_test(NAME load_balance_yade NEEDS yade COMMAND bash ${_lb} yade
            TIMEOUT 600 LABELS integration no_asan SERIAL)
