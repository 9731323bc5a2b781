// A key–value store in the browser's IndexedDB, for the pages' autosaves: one database of one
// object store, records put and got by key in transactions.

/**
 * Opens (creating on first use) the database `{ name, version, store }` with its one object
 * store; rejects where the browser has no IndexedDB or refuses it.
 */
export function openDatabase({ name, version, store }) {
  return new Promise((resolve, reject) => {
    if (typeof indexedDB === 'undefined') throw new Error('this browser has no IndexedDB');
    const request = indexedDB.open(name, version);
    request.onupgradeneeded = () => request.result.createObjectStore(store);
    request.onsuccess = () => resolve(request.result);
    request.onerror = () => reject(request.error);
    request.onblocked = () => reject(new Error('the storage is held by another tab'));
  });
}

/**
 * Runs `body(objectStore)` in one transaction of `mode` on `db`'s store `store`; resolves, once
 * the transaction completes, to the results of the requests `body` returns (an array of them,
 * or nothing).
 */
export function transact(db, store, mode, body) {
  return new Promise((resolve, reject) => {
    const tx = db.transaction(store, mode);
    const requests = body(tx.objectStore(store)) ?? [];
    tx.oncomplete = () => resolve(requests.map((r) => r.result));
    tx.onerror = () => reject(tx.error);
    tx.onabort = () => reject(tx.error ?? new Error('the browser aborted the write'));
  });
}
